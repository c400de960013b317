#!/usr/bin/env python3
"""Pools the trials of NEES runs split into parts (tests/covariance_nees.h).

    python3 scripts/nees_summary.py LOG [LOG ...] [--unwarned]
    python3 scripts/nees_summary.py --self-test

A NEES test of the covariance runs for hours on a large plan; with
UW_NEES_FIRST_TRIAL and UW_NEES_TRIALS its trials can be run in parts (over
sessions, on two machines), and each part prints one line per trial:

    [ trial 117 ] mean NEES poses 5.38 (251 poses), points 3.79 (31299 points)

This reads those lines from every LOG and prints what the test would have:
the mean NEES over every pose and point of every trial (pooled by their
counts), and the standard errors of the two means from the spread of the
per-trial means (the trials, not the points, are the independent draws).
Lines without counts (logs written before the counts were printed) weigh
their trial by the average count of the others, or equally when none has
counts; the summary says how many. --unwarned keeps only the trials whose
covariance did not warn, as ExpectCalibratedOrWarned judges a fused run.

A trial index seen twice must carry the same figures (the same seeds give
the same trial); anything else means the logs are of different runs, and
the script refuses them. Exits 1 when a mean is more than 10 % off its
dimension (6 for poses, 3 for points), as ExpectCalibrated fails.
"""
import math
import re
import sys
import tempfile

TRIAL = re.compile(
    r"^\[ trial (\d+) \] mean NEES poses (\S+?)(?: \((\d+) poses\))?, "
    r"points (\S+?)(?: \((\d+) points\))?( \(warned\))?$")


class Trial:
    def __init__(self, pose, num_poses, point, num_points, warned):
        self.pose = pose
        self.num_poses = num_poses
        self.point = point
        self.num_points = num_points
        self.warned = warned

    def key(self):
        return (self.pose, self.point, self.warned)


def read_trials(paths):
    """{index: Trial} over every log; raises ValueError on a conflict."""
    trials = {}
    for path in paths:
        with open(path) as log:
            for line_number, line in enumerate(log, 1):
                match = TRIAL.match(line.rstrip("\n"))
                if not match:
                    continue
                index = int(match.group(1))
                trial = Trial(float(match.group(2)),
                              int(match.group(3)) if match.group(3) else None,
                              float(match.group(4)),
                              int(match.group(5)) if match.group(5) else None,
                              match.group(6) is not None)
                if not all(math.isfinite(v) for v in (trial.pose, trial.point)):
                    raise ValueError(f"{path}:{line_number}: trial {index} "
                                     "has a non-finite NEES")
                seen = trials.get(index)
                if seen is not None and seen.key() != trial.key():
                    raise ValueError(
                        f"{path}:{line_number}: trial {index} differs from "
                        "the same trial in an earlier log: the logs are not "
                        "of one run")
                if seen is None or trial.num_poses is not None:
                    trials[index] = trial
    return trials


def pooled_mean(means, counts):
    known = [c for c in counts if c is not None]
    fill = sum(known) / len(known) if known else 1.0
    weights = [c if c is not None else fill for c in counts]
    return sum(m * w for m, w in zip(means, weights)) / sum(weights)


def standard_error(values):
    mean = sum(values) / len(values)
    squares = sum((v - mean) ** 2 for v in values)
    return math.sqrt(squares / (len(values) - 1) / len(values))


def summarise(trials):
    """(pose, pose_se, point, point_se) of a list of Trial (at least 2)."""
    poses = [t.pose for t in trials]
    points = [t.point for t in trials]
    return (pooled_mean(poses, [t.num_poses for t in trials]),
            standard_error(poses),
            pooled_mean(points, [t.num_points for t in trials]),
            standard_error(points))


def report(trials, unwarned):
    indices = sorted(trials)
    chosen = [trials[i] for i in indices
              if not (unwarned and trials[i].warned)]
    if len(chosen) < 2:
        print(f"nees_summary: {len(chosen)} trial(s); at least 2 are needed")
        return 1, None
    missing = sorted(set(range(indices[0], indices[-1] + 1)) - set(indices))
    uncounted = sum(1 for t in chosen if t.num_poses is None)
    pose, pose_se, point, point_se = summarise(chosen)
    print(f"{len(chosen)} trials ({indices[0]} to {indices[-1]}"
          + (f", {len(missing)} missing" if missing else "")
          + (f", {uncounted} weighed without counts" if uncounted else "")
          + (", unwarned only" if unwarned else "")
          + f"; {sum(t.warned for t in trials.values())} warned): "
          f"mean NEES poses {pose:.4f} +- {pose_se:.4f} (6), "
          f"points {point:.4f} +- {point_se:.4f} (3)")
    calibrated = abs(pose - 6.0) <= 0.6 and abs(point - 3.0) <= 0.3
    print("within 10 % of 6 and 3" if calibrated else
          "NOT within 10 % of 6 and 3")
    return (0 if calibrated else 1), (pose, point)


def self_test():
    """The pooling and the checks must be able to fail."""
    failures = []
    with tempfile.TemporaryDirectory() as root:
        def log(name, lines):
            path = f"{root}/{name}"
            with open(path, "w") as out:
                out.write("[ RUN      ] something\n" + "\n".join(lines) + "\n")
            return path

        old = log("old.log", [
            "[ trial 0 ] mean NEES poses 4, points 2",
            "[ trial 1 ] mean NEES poses 8, points 4 (warned)"])
        new = log("new.log", [
            "[ trial 1 ] mean NEES poses 8 (10 poses), points 4 "
            "(300 points) (warned)",
            "[ trial 2 ] mean NEES poses 6 (30 poses), points 3 "
            "(100 points)"])
        trials = read_trials([old, new])
        if sorted(trials) != [0, 1, 2]:
            failures.append(f"indices {sorted(trials)}")
        # Trial 0 has no counts: it weighs the others' average, 20 and 200.
        pose, _, point, _ = summarise([trials[i] for i in range(3)])
        if abs(pose - (4 * 20 + 8 * 10 + 6 * 30) / 60) > 1e-12:
            failures.append(f"pooled poses {pose}")
        if abs(point - (2 * 200 + 4 * 300 + 3 * 100) / 600) > 1e-12:
            failures.append(f"pooled points {point}")
        # Unwarned: trials 0 and 2; trial 0 weighs trial 2's 30 and 100.
        status, means = report(trials, unwarned=True)
        if means != (5.0, 2.5) or status != 1:
            failures.append(f"unwarned {means} exit {status}")
        near = log("near.log", [
            "[ trial 5 ] mean NEES poses 5.5 (10 poses), points 2.8 "
            "(100 points)",
            "[ trial 6 ] mean NEES poses 6.3 (10 poses), points 3.1 "
            "(100 points)"])
        status, _ = report(read_trials([near]), unwarned=False)
        if status != 0:
            failures.append("a calibrated pair judged off")
        clash = log("clash.log", ["[ trial 2 ] mean NEES poses 7, points 3"])
        try:
            read_trials([new, clash])
            failures.append("two different trials 2 accepted")
        except ValueError as error:
            if "trial 2 differs" not in str(error):
                failures.append(f"clash message: {error}")
    for failure in failures:
        print(f"self-test: {failure}")
    print(f"nees_summary self-test: {'failed' if failures else 'passed'}")
    return 1 if failures else 0


def main(argv):
    if "--self-test" in argv:
        return self_test()
    paths = [a for a in argv[1:] if not a.startswith("--")]
    if not paths:
        print(__doc__)
        return 2
    try:
        trials = read_trials(paths)
    except (OSError, ValueError) as error:
        print(f"nees_summary: {error}")
        return 2
    status, _ = report(trials, "--unwarned" in argv)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
