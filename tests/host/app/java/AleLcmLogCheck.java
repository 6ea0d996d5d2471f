// Reads an LCM log written by ale-slamd (--lcm-url file://LOG?mode=w) with LCM's own Java log
// reader and the Java classes lcm-gen made from app/lcm/*.lcm, and checks the first and last pose
// and status against the daemon's frame log and the replayed dataset's timestamps (and, when one
// is given, a TUM trajectory). A decoder we did not write: if our C++ encoding or the message
// definitions drift, this fails.
//
//   java -cp lcm.jar:CLASSES AleLcmLogCheck LOG FRAMES.csv DATASET_TIMES.csv [TRAJECTORY.tum]
import ale_lcm.pose_t;
import ale_lcm.status_t;
import java.io.BufferedReader;
import java.io.EOFException;
import java.io.FileReader;
import java.io.IOException;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.Map;

public final class AleLcmLogCheck {
  private static int failures = 0;
  private static int checks = 0;

  private static final String[] STATES = {"not_initialized", "initializing", "tracking", "lost", "relocalized"};
  private static final String[] CLASSES = {"extremely_dark", "dark", "normal", "bright"};

  private static void check(boolean ok, String what) {
    ++checks;
    if (!ok) {
      ++failures;
      System.err.println("FAIL: " + what);
    }
  }

  private static void near(double got, double want, double tol, String what) {
    check(Math.abs(got - want) <= tol, what + ": " + got + ", expected " + want + " +- " + tol);
  }

  // Rows of a CSV with a '#' header naming the columns.
  private static List<Map<String, String>> readCsv(String path) throws IOException {
    List<Map<String, String>> rows = new ArrayList<>();
    try (BufferedReader in = new BufferedReader(new FileReader(path))) {
      String[] names = null;
      for (String line; (line = in.readLine()) != null;) {
        if (line.isEmpty()) continue;
        if (line.startsWith("#")) {
          names = line.substring(1).split(",");
          for (int i = 0; i < names.length; ++i) names[i] = names[i].trim();
          continue;
        }
        String[] v = line.split(",");
        Map<String, String> row = new HashMap<>();
        for (int i = 0; i < v.length && names != null && i < names.length; ++i) row.put(names[i], v[i].trim());
        if (names == null) row.put("0", v[0].trim());
        rows.add(row);
      }
    }
    return rows;
  }

  // TUM rows "t_s tx ty tz qx qy qz qw" keyed by their time in ns (rounded to the microsecond).
  private static Map<Long, double[]> readTum(String path) throws IOException {
    Map<Long, double[]> rows = new HashMap<>();
    try (BufferedReader in = new BufferedReader(new FileReader(path))) {
      for (String line; (line = in.readLine()) != null;) {
        line = line.trim();
        if (line.isEmpty() || line.startsWith("#")) continue;
        String[] v = line.split("\\s+");
        double[] p = new double[8];
        for (int i = 0; i < 8; ++i) p[i] = Double.parseDouble(v[i]);
        rows.put(Math.round(p[0] * 1e6), p);
      }
    }
    return rows;
  }

  private static void checkPose(pose_t p, Map<String, String> frame, long datasetNs, Map<Long, double[]> tum,
                                String which) {
    check(p.timestamp_ns == Long.parseLong(frame.get("timestamp_ns")), which + " pose timestamp vs frame log");
    check(p.timestamp_ns == datasetNs, which + " pose timestamp " + p.timestamp_ns + " vs dataset " + datasetNs);
    check(p.frame_sequence == Long.parseLong(frame.get("sequence")), which + " pose frame_sequence");
    check(p.state >= 0 && p.state < STATES.length && STATES[p.state].equals(frame.get("state")),
          which + " pose state " + p.state + " vs " + frame.get("state"));
    check(p.inliers == Integer.parseInt(frame.get("inliers")), which + " pose inliers");
    double qn = 0;
    for (double q : p.orientation) qn += q * q;
    near(qn, 1.0, 1e-9, which + " pose |q_wc|^2");
    for (double x : p.position) check(Double.isFinite(x), which + " pose position finite");
    if (!p.body_valid) {
      for (int i = 0; i < 3; ++i) near(p.body_position[i], p.position[i], 0, which + " body = camera position");
      for (int i = 0; i < 4; ++i) near(p.body_orientation[i], p.orientation[i], 0, which + " body = camera orientation");
      near(p.T_bc_orientation[0], 1.0, 0, which + " T_bc identity");
    }
    for (double v : p.velocity_mps) check(Double.isFinite(v), which + " velocity finite");
    check(p.map_id == 0, which + " map_id 0 (no reset)");
    check(!p.relocalized, which + " not relocalized");
    if (tum != null && p.state != pose_t.NOT_INITIALIZED) {
      double[] t = tum.get(Math.round(p.timestamp_ns / 1e3));
      check(t != null, which + " pose has a trajectory row");
      if (t != null) {
        for (int i = 0; i < 3; ++i) near(p.position[i], t[1 + i], 1e-6, which + " position[" + i + "] vs trajectory");
        near(p.orientation[0], t[7], 1e-6, which + " q_w vs trajectory");
        for (int i = 0; i < 3; ++i) near(p.orientation[1 + i], t[4 + i], 1e-6, which + " q[" + i + "] vs trajectory");
      }
    }
  }

  // relocalised: the frame log's rows in state relocalized up to this frame.
  private static void checkStatus(status_t s, Map<String, String> frame, int relocalised, String which) {
    check(s.timestamp_ns == Long.parseLong(frame.get("timestamp_ns")), which + " status timestamp");
    check(s.state >= 0 && s.state < STATES.length && STATES[s.state].equals(frame.get("state")), which + " status state");
    check(s.brightness_class >= 0 && s.brightness_class < CLASSES.length &&
              CLASSES[s.brightness_class].equals(frame.get("brightness")),
          which + " brightness_class " + s.brightness_class + " vs " + frame.get("brightness"));
    near(s.mean_intensity, Double.parseDouble(frame.get("mean")), 0.006, which + " mean_intensity");
    check(s.features == Integer.parseInt(frame.get("features")), which + " features");
    check(s.inliers == Integer.parseInt(frame.get("inliers")), which + " inliers");
    check(s.frame_time_ms > 0, which + " frame_time_ms > 0");
    check(s.relocalisations == relocalised,
          which + " relocalisations " + s.relocalisations + ", the frame log has " + relocalised + " relocalized rows");
    near(s.place_ms, Double.parseDouble(frame.get("place_ms")), 0.0006, which + " place_ms vs the frame log");
    check(s.loops_closed == Integer.parseInt(frame.get("loops")),
          which + " loops_closed " + s.loops_closed + ", the frame log's loops " + frame.get("loops"));
    check(s.loops_refused >= 0, which + " loops_refused " + s.loops_refused + " >= 0");
    near(s.loop_ms, Double.parseDouble(frame.get("loop_ms")), 0.0006, which + " loop_ms vs the frame log");
    check(s.merges == Integer.parseInt(frame.get("merges")),
          which + " merges " + s.merges + ", the frame log's merges " + frame.get("merges"));
    check(s.merges_refused == Integer.parseInt(frame.get("merges_refused")),
          which + " merges_refused " + s.merges_refused + ", the frame log's " + frame.get("merges_refused"));
    check(s.camera_state == status_t.CAMERA_STREAMING, which + " camera streaming");
    check(s.frames_skipped == 0 && s.frame_errors == 0 && s.camera_reconnects == 0, which + " no skips, errors, reconnects");
    check(s.frames_dropped == 0, which + " no dropped frames");
    check(s.pool_count == s.pool_names.length && s.pool_count == s.pool_high_water.length, which + " pool arrays");
    boolean cameraPool = false;
    for (int i = 0; i < s.pool_count; ++i) {
      check(s.pool_high_water[i] <= s.pool_capacity[i], which + " pool " + s.pool_names[i] + " within capacity");
      cameraPool |= s.pool_names[i].equals("camera_buffers") && s.pool_high_water[i] >= 1;
    }
    check(cameraPool, which + " status has the camera's buffers with a high-water mark");
    check(s.stage_count > 0 && s.stage_count == s.stage_names.length, which + " per-stage times present");
    for (int i = 0; i < s.stage_count; ++i)
      check(!s.stage_names[i].isEmpty() && s.stage_ms[i] >= 0, which + " stage " + s.stage_names[i]);
    check(s.config_generation == 0 && !s.paused, which + " generation 0, not paused");
    check(s.publish_errors == 0 && s.commands_received == 0 && s.commands_rejected == 0, which + " counters 0");
    check(s.last_error.isEmpty(), which + " no error: '" + s.last_error + "'");
    check(s.recorder_state == status_t.RECORDER_OFF && s.frames_recorded == 0 && s.frames_not_recorded == 0,
          which + " recorder off");
    check(s.map_saves == 0 && s.map_save_failures == 0 && s.last_save_ms == 0, which + " no map saved (no map.save)");
  }

  public static void main(String[] args) throws IOException {
    if (args.length < 3) {
      System.err.println("usage: AleLcmLogCheck LOG FRAMES.csv DATASET_TIMES.csv [TRAJECTORY.tum]");
      System.exit(2);
    }
    lcm.logging.Log log = new lcm.logging.Log(args[0], "r");
    List<pose_t> poses = new ArrayList<>();
    List<status_t> statuses = new ArrayList<>();
    Map<String, Integer> others = new HashMap<>();
    try {
      for (;;) {
        lcm.logging.Log.Event ev = log.readNext();
        if (ev.channel.equals("ALE_POSE"))
          poses.add(new pose_t(ev.data));  // throws on a fingerprint or length mismatch
        else if (ev.channel.equals("ALE_STATUS"))
          statuses.add(new status_t(ev.data));
        else
          others.merge(ev.channel, 1, Integer::sum);
      }
    } catch (EOFException end) {
      // the end of the log
    }
    log.close();
    List<Map<String, String>> frames = readCsv(args[1]);
    List<Map<String, String>> dataset = readCsv(args[2]);
    Map<Long, double[]> tum = args.length > 3 ? readTum(args[3]) : null;
    check(!poses.isEmpty(), "the log has poses");
    check(others.isEmpty(), "only pose and status channels: " + others);
    check(poses.size() == frames.size(), poses.size() + " poses, " + frames.size() + " frame-log rows");
    check(statuses.size() == frames.size(), statuses.size() + " statuses, " + frames.size() + " frame-log rows");
    check(frames.size() == dataset.size(), frames.size() + " frames processed, dataset has " + dataset.size());
    if (!poses.isEmpty() && poses.size() == frames.size() && frames.size() == dataset.size() &&
        statuses.size() == frames.size()) {
      final int last = poses.size() - 1;
      final String timeKey = "timestamp [ns]";
      long firstNs = Long.parseLong(dataset.get(0).containsKey(timeKey) ? dataset.get(0).get(timeKey) : dataset.get(0).get("0"));
      long lastNs = Long.parseLong(dataset.get(last).containsKey(timeKey) ? dataset.get(last).get(timeKey) : dataset.get(last).get("0"));
      checkPose(poses.get(0), frames.get(0), firstNs, tum, "first");
      checkPose(poses.get(last), frames.get(last), lastNs, tum, "last");
      int relocalised = 0;
      for (Map<String, String> f : frames) relocalised += f.get("state").equals("relocalized") ? 1 : 0;
      checkStatus(statuses.get(0), frames.get(0), frames.get(0).get("state").equals("relocalized") ? 1 : 0, "first");
      checkStatus(statuses.get(last), frames.get(last), relocalised, "last");
      for (int i = 1; i < poses.size(); ++i)
        check(poses.get(i).frame_sequence == poses.get(i - 1).frame_sequence + 1, "pose " + i + " follows its predecessor");
    }
    System.out.println("AleLcmLogCheck: " + poses.size() + " poses, " + statuses.size() + " statuses; " + checks +
                       " checks, " + failures + " failed");
    System.exit(failures == 0 ? 0 : 1);
  }
}
