// A motion controller's side of the command channel, run against a live ale-slamd in another
// process (both on LCM's tcpq:// provider through LCM's Java TCPService hub, so nothing needs
// multicast): it waits for a status showing a map with at least three keyframes, sends SAVE_MAP
// to MAP, RESET_MAP and an unknown command, and checks each reply (id, kind, result, what the
// save wrote), that the status counts the save and that a status after the reset carries the
// next map id; then LOAD_MAP of CORRUPT (refused, the map as it was), LOAD_MAP of MAP (the saved
// map back, with its id and keyframes) and SAVE_MAP without a path (no map.save: BAD_ARGUMENT).
// LCM's Java classes and the ones lcm-gen made from app/lcm decode everything: a client we did
// not write.
//
//   java -cp lcm.jar:CLASSES AleLcmCommandCheck URL TIMEOUT_S MAP CORRUPT
// Prints "AleLcmCommandCheck: ready" once subscribed, then one line per reply and a summary;
// exits 1 on a failed check or when the daemon does not answer within TIMEOUT_S.
import ale_lcm.command_reply_t;
import ale_lcm.command_t;
import ale_lcm.status_t;
import java.io.IOException;
import java.util.ArrayList;
import java.util.List;
import lcm.lcm.LCM;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMSubscriber;

public final class AleLcmCommandCheck implements LCMSubscriber {
  private static int failures = 0;
  private static int checks = 0;

  private static void check(boolean ok, String what) {
    ++checks;
    if (!ok) {
      ++failures;
      System.err.println("FAIL: " + what);
    }
  }

  private final List<status_t> statuses = new ArrayList<>();
  private final List<command_reply_t> replies = new ArrayList<>();
  // how many statuses had arrived when each reply did (LCM over TCP keeps the daemon's order)
  private final java.util.Map<Long, Integer> statusesBeforeReply = new java.util.HashMap<>();

  @Override
  public synchronized void messageReceived(LCM lcm, String channel, LCMDataInputStream in) {
    try {
      if (channel.equals("ALE_STATUS")) statuses.add(new status_t(in));
      if (channel.equals("ALE_COMMAND_REPLY")) {
        command_reply_t r = new command_reply_t(in);
        replies.add(r);
        statusesBeforeReply.put(r.command_id, statuses.size());
      }
    } catch (IOException e) {
      check(false, "undecodable message on " + channel + ": " + e);
    }
    notifyAll();
  }

  private interface Condition {
    boolean holds();
  }

  // Waits until `c` holds (true) or the deadline passes (false).
  private synchronized boolean await(Condition c, long deadlineMs) throws InterruptedException {
    while (!c.holds()) {
      long left = deadlineMs - System.currentTimeMillis();
      if (left <= 0) return false;
      wait(left);
    }
    return true;
  }

  private synchronized command_reply_t replyTo(long id) {
    for (command_reply_t r : replies)
      if (r.command_id == id) return r;
    return null;
  }

  private synchronized status_t lastStatus() { return statuses.isEmpty() ? null : statuses.get(statuses.size() - 1); }

  // The first status published after the reply to `id`: the first frame the command applied to.
  private synchronized status_t statusAfterReply(long id) {
    Integer before = statusesBeforeReply.get(id);
    return before == null || statuses.size() <= before ? null : statuses.get(before);
  }

  private static command_t command(long id, byte kind, String argument) {
    command_t c = new command_t();
    c.command_id = id;
    c.command = kind;
    c.argument = argument;
    return c;
  }

  public static void main(String[] args) throws Exception {
    if (args.length != 4) {
      System.err.println("usage: AleLcmCommandCheck URL TIMEOUT_S MAP CORRUPT");
      System.exit(2);
    }
    final long deadline = System.currentTimeMillis() + (long) (Double.parseDouble(args[1]) * 1000.0);
    final String mapPath = args[2], corruptPath = args[3];
    LCM lcm = new LCM(args[0]);
    AleLcmCommandCheck self = new AleLcmCommandCheck();
    lcm.subscribe("ALE_STATUS", self);
    lcm.subscribe("ALE_COMMAND_REPLY", self);
    System.out.println("AleLcmCommandCheck: ready");
    System.out.flush();

    // a map worth resetting
    final boolean mapped = self.await(() -> {
      status_t s = self.lastStatus();
      return s != null && s.keyframes >= 3;
    }, deadline);
    check(mapped, "a status with at least 3 keyframes (the daemon's map) before the timeout");
    if (!mapped) finish();
    final status_t before = self.lastStatus();

    final long resetId = 7001, saveId = 7002, unknownId = 7003;
    lcm.publish("ALE_COMMAND", command(saveId, command_t.SAVE_MAP, mapPath));
    lcm.publish("ALE_COMMAND", command(resetId, command_t.RESET_MAP, ""));
    lcm.publish("ALE_COMMAND", command(unknownId, (byte) 99, ""));
    final boolean answered = self.await(
        () -> self.replyTo(resetId) != null && self.replyTo(saveId) != null && self.replyTo(unknownId) != null, deadline);
    check(answered, "a reply to each of the three commands before the timeout");
    if (!answered) finish();
    self.checkReplies(new long[] {resetId, saveId, unknownId}, new byte[] {command_t.RESET_MAP, command_t.SAVE_MAP, 99},
                      new byte[] {command_reply_t.OK, command_reply_t.OK, command_reply_t.UNKNOWN_COMMAND});
    final String saved = self.replyTo(saveId).message;
    final java.util.regex.Matcher m =
        java.util.regex.Pattern.compile("map saved to \\Q" + mapPath + "\\E: ([0-9]+) keyframes, .*").matcher(saved);
    final int savedKeyframes = m.matches() ? Integer.parseInt(m.group(1)) : -1;
    check(savedKeyframes >= 3, "the save's reply names the file and the map's keyframes (3 or more): '" + saved + "'");
    check(saved.matches(".* [0-9]+ bytes, [0-9.]+ ms"), "the save's reply gives its size and time: '" + saved + "'");
    // the reset took: the status of the frame after it has a new map id, and counts the save
    final boolean reset = self.await(() -> self.statusAfterReply(resetId) != null, deadline);
    check(reset, "a status after the reply to RESET_MAP");
    if (!reset) finish();
    status_t afterReset = self.statusAfterReply(resetId);
    System.out.println("AleLcmCommandCheck: map " + before.map_id + " with " + before.keyframes + " keyframes saved, then map "
                       + afterReset.map_id + " with " + afterReset.keyframes);
    check(afterReset.map_id == before.map_id + 1, "the new map id is the next one");
    check(afterReset.map_saves == 1 && afterReset.map_save_failures == 0 && afterReset.last_save_ms > 0,
          "the status counts one save (map_saves " + afterReset.map_saves + ", failures " + afterReset.map_save_failures
              + ", last_save_ms " + afterReset.last_save_ms + ")");

    // a file that is not a map is refused and changes nothing; the saved one brings its map back
    final long corruptId = 7004, loadId = 7005, noPathId = 7006;
    lcm.publish("ALE_COMMAND", command(corruptId, command_t.LOAD_MAP, corruptPath));
    lcm.publish("ALE_COMMAND", command(loadId, command_t.LOAD_MAP, mapPath));
    lcm.publish("ALE_COMMAND", command(noPathId, command_t.SAVE_MAP, ""));
    final boolean loaded = self.await(
        () -> self.replyTo(corruptId) != null && self.replyTo(loadId) != null && self.replyTo(noPathId) != null, deadline);
    check(loaded, "a reply to each of the two loads and the save without a path before the timeout");
    if (!loaded) finish();
    self.checkReplies(new long[] {corruptId, loadId, noPathId},
                      new byte[] {command_t.LOAD_MAP, command_t.LOAD_MAP, command_t.SAVE_MAP},
                      new byte[] {command_reply_t.FAILED, command_reply_t.OK, command_reply_t.BAD_ARGUMENT});
    check(self.replyTo(corruptId).message.startsWith("map file " + corruptPath + " not loaded: ")
              && self.replyTo(corruptId).message.endsWith("; the map is as it was"),
          "the refused load says so");
    check(self.replyTo(loadId).message.startsWith("map loaded from " + mapPath + ": ")
              && self.replyTo(loadId).message.endsWith("relocalising in map " + before.map_id),
          "the load names the file and the saved map's id " + before.map_id);
    // the frame after the load: the saved map, its id (the frames after it may start a new map
    // when none relocalises in it within slam.lost_timeout_s)
    final boolean back = self.await(() -> self.statusAfterReply(loadId) != null, deadline);
    check(back, "a status after the reply to LOAD_MAP");
    if (back) {
      status_t s = self.statusAfterReply(loadId);
      System.out.println("AleLcmCommandCheck: map " + s.map_id + " loaded back with " + s.keyframes + " keyframes");
      check(s.map_id == before.map_id, "the status after LOAD_MAP is in the saved map's id " + before.map_id);
      check(s.keyframes >= savedKeyframes, "the loaded map has the " + savedKeyframes + " keyframes saved");
      check(s.map_saves == 1, "no other save was made (map_saves " + s.map_saves + ")");
    }
    finish();
  }

  private void checkReplies(long[] ids, byte[] kinds, byte[] results) {
    for (int i = 0; i < ids.length; ++i) {
      command_reply_t r = replyTo(ids[i]);
      System.out.println("AleLcmCommandCheck: reply to " + ids[i] + ": command " + r.command + " result " + r.result
                         + " '" + r.message + "'");
      check(r.command == kinds[i], "reply " + ids[i] + " names command " + r.command + ", expected " + kinds[i]);
      check(r.result == results[i], "reply " + ids[i] + " result " + r.result + ", expected " + results[i]);
      check(r.timestamp_ns > 0, "reply " + ids[i] + " has a timestamp");
    }
  }

  private static void finish() {
    System.out.println("AleLcmCommandCheck: " + checks + " checks, " + failures + " failed");
    System.out.flush();
    System.exit(failures == 0 ? 0 : 1);
  }
}
