"""Made-up renders for the bench-table tests (loop_bench_eval_test.sh, lane_bench_eval_test.sh)."""
import os

HEADER = "# timestamp tx ty tz qx qy qz qw\n"


def write_render(work, name, gt):
    """WORK/renders/NAME/groundtruth.txt (TUM, identity rotations) and its mav0/cam0/data.csv (one
    image a pose) from gt, a list of (t, x, y, z)."""
    os.makedirs(work + "/renders/%s/mav0/cam0" % name)
    with open(work + "/renders/%s/groundtruth.txt" % name, "w") as f:
        f.write(HEADER)
        for t, x, y, z in gt:
            f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % (t, x, y, z))
    with open(work + "/renders/%s/mav0/cam0/data.csv" % name, "w") as f:
        f.write("#timestamp [ns],filename\n")
        for t, *_ in gt:
            f.write("%d,%d.png\n" % (round(t * 1e9), round(t * 1e9)))
