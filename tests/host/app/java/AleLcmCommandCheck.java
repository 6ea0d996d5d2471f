// A motion controller's side of the command channel, run against a live ale-slamd in another
// process (both on LCM's tcpq:// provider through LCM's Java TCPService hub, so nothing needs
// multicast): it waits for a status showing a map with at least three keyframes, sends RESET_MAP,
// SAVE_MAP and an unknown command, and checks each reply (id, kind, result) and that a status
// after the reset carries the next map id. LCM's Java classes and the ones lcm-gen
// made from app/lcm decode everything: a client we did not write.
//
//   java -cp lcm.jar:CLASSES AleLcmCommandCheck URL TIMEOUT_S
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

  @Override
  public synchronized void messageReceived(LCM lcm, String channel, LCMDataInputStream in) {
    try {
      if (channel.equals("ALE_STATUS")) statuses.add(new status_t(in));
      if (channel.equals("ALE_COMMAND_REPLY")) replies.add(new command_reply_t(in));
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

  private static command_t command(long id, byte kind, String argument) {
    command_t c = new command_t();
    c.command_id = id;
    c.command = kind;
    c.argument = argument;
    return c;
  }

  public static void main(String[] args) throws Exception {
    if (args.length != 2) {
      System.err.println("usage: AleLcmCommandCheck URL TIMEOUT_S");
      System.exit(2);
    }
    final long deadline = System.currentTimeMillis() + (long) (Double.parseDouble(args[1]) * 1000.0);
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
    lcm.publish("ALE_COMMAND", command(resetId, command_t.RESET_MAP, ""));
    lcm.publish("ALE_COMMAND", command(saveId, command_t.SAVE_MAP, "/tmp/map.bin"));
    lcm.publish("ALE_COMMAND", command(unknownId, (byte) 99, ""));
    final boolean answered = self.await(
        () -> self.replyTo(resetId) != null && self.replyTo(saveId) != null && self.replyTo(unknownId) != null, deadline);
    check(answered, "a reply to each of the three commands before the timeout");
    if (!answered) finish();
    final long[] ids = {resetId, saveId, unknownId};
    final byte[] kinds = {command_t.RESET_MAP, command_t.SAVE_MAP, 99};
    final byte[] results = {command_reply_t.OK, command_reply_t.NOT_SUPPORTED, command_reply_t.UNKNOWN_COMMAND};
    for (int i = 0; i < 3; ++i) {
      command_reply_t r = self.replyTo(ids[i]);
      System.out.println("AleLcmCommandCheck: reply to " + ids[i] + ": command " + r.command + " result " + r.result
                         + " '" + r.message + "'");
      check(r.command == kinds[i], "reply " + ids[i] + " names command " + r.command + ", expected " + kinds[i]);
      check(r.result == results[i], "reply " + ids[i] + " result " + r.result + ", expected " + results[i]);
      check(r.timestamp_ns > 0, "reply " + ids[i] + " has a timestamp");
    }
    // the reset took: a later status with a new map id and fewer keyframes than before
    final boolean reset = self.await(() -> {
      status_t s = self.lastStatus();
      return s != null && s.map_id != before.map_id;
    }, deadline);
    check(reset, "a status with a new map id after RESET_MAP (map " + before.map_id + " had " + before.keyframes
                 + " keyframes)");
    if (reset) {
      status_t s = self.lastStatus();
      System.out.println("AleLcmCommandCheck: map " + before.map_id + " with " + before.keyframes + " keyframes, then map "
                         + s.map_id + " with " + s.keyframes);
      check(s.map_id == before.map_id + 1, "the new map id is the next one");
    }
    finish();
  }

  private static void finish() {
    System.out.println("AleLcmCommandCheck: " + checks + " checks, " + failures + " failed");
    System.out.flush();
    System.exit(failures == 0 ? 0 : 1);
  }
}
