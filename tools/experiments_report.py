#!/usr/bin/env python3
"""The thesis experiment matrix and its report, docs/experiments.md.

Python 3 standard library only. Two commands:

  experiments_report.py matrix
      prints the matrix, one run a line: "<scenario> <preset> <strategy>"
      (tools/experiments.sh runs exactly these).

  experiments_report.py report --runs DIR [--status FILE] [--img-dir DIR] [--out FILE]
      reads DIR/<scenario>_<preset>_<strategy>/summary.json for every run of the matrix and
      writes the report (default docs/experiments.md) whole (temporary file, then rename).
      --status is a file of "<scenario> <preset> <strategy> <exit code> [message]" lines, one
      per run, as tools/experiments.sh writes it; runs that left no readable summary are
      reported as such, never skipped. Images are linked as <img-dir>/<run>_trajectory.png and
      _velocities.png, relative to the report, when they exist.

The discussion between DISCUSSION_BEGIN and DISCUSSION_END is written by hand: a re-run keeps
whatever text an existing report has there.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

# ---- The matrix: scenarios (in report order) x robot/strategy combinations ----

SCENARIOS = [
    # name, closed (a loop, scored by laps; no end mark), one-line summary for the report
    ("circle", True, "closed white circle, radius 3 m (18.85 m), no obstacles: one lap"),
    ("corners", False, "open white course, 35.1 m, five 90 deg corners; a cylinder and a box "
     "on two straights; end mark"),
    ("smooth", False, "the corners course with 1.2 m arcs and a 45 deg diagonal, 31.4 m; a "
     "cylinder, and a box 0.9 m past the end of a curve; end mark"),
    ("corners_red", False, "corners in red tape with three obstacles (two cylinders, a box)"),
    ("smooth_red", False, "smooth in red tape with three obstacles (two cylinders, a box)"),
]

COMBOS = [
    ("campero", "marks"),
    ("campero", "line_priority"),
    ("pioneer3at", "marks"),
    ("pioneer3at", "pid"),
]

DISCUSSION_BEGIN = "<!-- discussion: written by hand from the table above -->"
DISCUSSION_END = ("<!-- end of discussion (the text between the two markers is kept when "
                  "regenerating) -->")
DISCUSSION_PLACEHOLDER = (
    "**TO BE WRITTEN from the numbers above** (by hand; `tools/experiments.sh` keeps this text "
    "when it regenerates the page): which strategy wins where, on which robot, and why - "
    "corners against arcs, bypasses out of a curve, red tape - and where each one fails.")

# ---- The hand-written parts of the page (the template) ----

INTRO = """\
# Experiments

The thesis experiments, re-run in the simulator: five scenarios, each driven by the two robots
and the strategies they can use - Campero (mecanum) with `marks` and `line_priority`, Pioneer 3-AT
(differential) with `marks` and `pid` - 20 runs in all. Every run starts on the tape's beginning,
aligned with it, at a commanded 0.5 m/s, and is scored against its scenario's `expect` block:
for the open courses, reach and stop on the yellow end mark (`end_reached`), cover the whole path
in order (`min_progress: 1.0`), no collision, cross-track RMS at most 0.03 m; for the circle, one
full lap with the same collision, progress and cross-track limits.

| scenario | what it is |
| --- | --- |
{scenario_rows}

Files: `scenarios/<name>.yaml` (geometry and expectations are described in each file). Each run
is also a CTest test, `experiment.<scenario>.<preset>.<strategy>` (label `experiment`).
"""

REGENERATE = """\
## How to regenerate

```sh
cmake --preset host && cmake --build --preset host --target carril_sim
bash tools/experiments.sh            # or: bash tools/experiments.sh <build dir>
```

It runs the 20 runs with `carril_sim --scenario scenarios/<scenario>.yaml --preset <preset>
--strategy <strategy> --out <build dir>/runs/<scenario>_<preset>_<strategy> --quiet`, copies each
run's `trajectory.png` and `velocities.png` to `docs/img/<scenario>_<preset>_<strategy>_*.png` and
rewrites this page from the runs' `summary.json` files with `tools/experiments_report.py`. The
tables and images are generated; the discussion below them is written by hand and kept across
re-runs (the text between the two `discussion` comment markers).
"""

COLUMNS_NOTE = """\
Columns: **result** is how the run ended (`end_reached`: stopped on the end mark; `time_limit`:
the scenario's duration ran out; `fault`: the firmware latched a fault and stopped; `aborted`);
**passed** is whether the `expect` block was met; **progress** is the fraction of the path covered
in order (a bypass counts once the robot is back on the tape); **time** is the simulated time
when the run ended (the time to the end mark when `end_reached`); **cross-track** is the distance
from the robot's centre to the tape while following it (RMS and max); **lost / found** are the
line-lost and line-reacquired events; **avoided** are obstacles bypassed; **stop error** is the
distance from the robot's centre to the end mark's centre once stopped; **max |wz|** is the largest
yaw rate; **mean speed** is distance travelled over time.
"""


# ---- Reading the runs ----

def run_id(scenario, preset, strategy):
    return f"{scenario}_{preset}_{strategy}"


def read_status(path):
    """{run id: (exit code or None, message)} from the status file; missing file: {}."""
    status = {}
    if not path:
        return status
    try:
        with open(path, encoding="utf-8") as f:
            for line in f:
                parts = line.rstrip("\n").split(" ", 4)
                if len(parts) < 4:
                    continue
                try:
                    code = int(parts[3])
                except ValueError:
                    code = None
                status[run_id(*parts[:3])] = (code, parts[4] if len(parts) > 4 else "")
    except OSError:
        pass
    return status


def read_summary(path):
    """(summary dict or None, problem text or None)."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except FileNotFoundError:
        return None, "no summary.json"
    except (OSError, ValueError) as e:
        return None, f"unreadable summary.json ({e.__class__.__name__})"
    if not isinstance(data, dict):
        return None, "unreadable summary.json (not an object)"
    return data, None


# ---- Formatting ----

def num(v, digits):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        return "-"
    return f"{v:.{digits}f}"


def integer(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return "-"
    return str(int(v))


def yes_no(v):
    return "yes" if v is True else ("no" if v is False else "-")


def md_escape(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def verdict(summary):
    if summary is None:
        return "NO OUTPUT"
    return "**PASS**" if summary.get("passed") is True else "FAIL"


# ---- Building the page ----

def overview_table(results):
    head = "| scenario | " + " | ".join(f"{p} + `{s}`" for p, s in COMBOS) + " |"
    rule = "| --- |" + " --- |" * len(COMBOS)
    rows = [head, rule]
    for name, _closed, _what in SCENARIOS:
        cells = []
        for preset, strategy in COMBOS:
            r = results[run_id(name, preset, strategy)]
            s = r["summary"]
            if s is None:
                cells.append("NO OUTPUT")
            else:
                cells.append(f"{verdict(s)} ({md_escape(s.get('result') or '?')}, "
                             f"progress {num(s.get('progress'), 2)})")
        rows.append(f"| [{name}](#{name}) | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def scenario_section(name, closed, what, results, img_dir_rel, img_dir_abs):
    out = [f"## {name}", "", f"`scenarios/{name}.yaml`: {what}.", ""]
    cols = ["robot", "strategy", "result", "passed", "progress", "end reached"]
    if closed:
        cols.append("laps")
    cols += ["time [s]", "cross-track RMS [m]", "cross-track max [m]", "lost / found",
             "collisions", "avoided", "stop error [m]", "max \\|wz\\| [rad/s]",
             "mean speed [m/s]", "plots"]
    out.append("| " + " | ".join(cols) + " |")
    out.append("|" + " --- |" * len(cols))
    notes = []
    gallery = []
    for preset, strategy in COMBOS:
        rid = run_id(name, preset, strategy)
        r = results[rid]
        s = r["summary"]
        links = []
        for kind in ("trajectory", "velocities"):
            fname = f"{rid}_{kind}.png"
            if os.path.isfile(os.path.join(img_dir_abs, fname)):
                links.append(f"[{kind}]({img_dir_rel}/{fname})")
        plots = " · ".join(links) if links else "-"
        if s is None:
            cells = [preset, f"`{strategy}`", "NO OUTPUT", "no"] + ["-"] * (len(cols) - 5)
            cells.append(plots)
            out.append("| " + " | ".join(cells) + " |")
            notes.append(f"- {preset} + `{strategy}`: no result: {md_escape(r['problem'])}.")
            continue
        cells = [preset, f"`{strategy}`", md_escape(s.get("result") or "-"), verdict(s),
                 num(s.get("progress"), 3), yes_no(s.get("end_reached"))]
        if closed:
            cells.append(integer(s.get("laps")))
        cells += [num(s.get("sim_time_s"), 1), num(s.get("cross_track_rms_m"), 4),
                  num(s.get("cross_track_max_m"), 3),
                  integer(s.get("line_lost_events")) + " / " +
                  integer(s.get("line_reacquired_events")),
                  integer(s.get("collisions")), integer(s.get("obstacles_avoided")),
                  num(s.get("end_stop_error_m"), 3), num(s.get("max_abs_wz_radps"), 2),
                  num(s.get("mean_speed_mps"), 3), plots]
        out.append("| " + " | ".join(cells) + " |")
        unmet = s.get("unmet_expectations") or []
        extra = []
        if s.get("fault"):
            extra.append(f"fault: {md_escape(s['fault'])}")
        if s.get("final_state"):
            extra.append(f"final state {md_escape(s['final_state'])}")
        if unmet:
            extra.append("unmet: " + "; ".join(md_escape(u) for u in unmet))
        if r["problem"]:
            extra.append(md_escape(r["problem"]))
        if unmet or s.get("fault") or r["problem"]:
            notes.append(f"- {preset} + `{strategy}`: " + ", ".join(extra) + ".")
        traj = f"{rid}_trajectory.png"
        if os.path.isfile(os.path.join(img_dir_abs, traj)):
            gallery.append(f'<a href="{img_dir_rel}/{traj}"><img src="{img_dir_rel}/{traj}" '
                           f'width="400" alt="{name}, {preset}, {strategy}: trajectory"></a>')
    if notes:
        out += ["", "Why runs did not pass:", ""] + notes
    if gallery:
        out += ["", "Trajectories (in table order; click for full size):", "", "<p>"]
        out += gallery
        out += ["</p>"]
    out.append("")
    return "\n".join(out)


def source_line():
    """'Generated from commit abc1234' (with local changes, when the tree is dirty), or ''."""
    here = os.path.dirname(os.path.abspath(__file__))
    def git(*args):
        return subprocess.run(["git", "-C", here, *args], capture_output=True, text=True,
                              timeout=10, check=True).stdout.strip()
    try:
        commit = git("rev-parse", "--short", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return ""
    if not commit:
        return ""
    return f"Generated from commit `{commit}`" + (" with local changes" if dirty else "") + "."


def kept_discussion(existing_text):
    """The hand-written discussion of an existing report, or None when there is none.

    Raises ValueError when the begin marker is there without its end marker: the page cannot be
    rewritten without risking a human's text."""
    b = existing_text.find(DISCUSSION_BEGIN)
    if b < 0:
        return None
    start = b + len(DISCUSSION_BEGIN)
    e = existing_text.find(DISCUSSION_END, start)
    if e < 0:
        raise ValueError("the discussion's begin marker has no end marker after it")
    return existing_text[start:e].strip("\n")


def build_page(results, img_dir_rel, img_dir_abs, discussion):
    n = len(results)
    with_output = sum(1 for r in results.values() if r["summary"] is not None)
    passed = sum(1 for r in results.values()
                 if r["summary"] is not None and r["summary"].get("passed") is True)
    scenario_rows = "\n".join(f"| `{name}` | {what} |" for name, _c, what in SCENARIOS)
    parts = [INTRO.format(scenario_rows=scenario_rows), REGENERATE]
    parts.append("## Results\n")
    src = source_line()
    parts.append((src + " " if src else "") +
                 f"{n} runs: {with_output} left a summary, {passed} passed their scenario's "
                 "expectations.\n")
    parts.append(overview_table(results) + "\n")
    parts.append(COLUMNS_NOTE)
    for name, closed, what in SCENARIOS:
        parts.append(scenario_section(name, closed, what, results, img_dir_rel, img_dir_abs))
    parts.append("## Which strategy wins where\n")
    parts.append(DISCUSSION_BEGIN)
    parts.append(discussion if discussion is not None and discussion.strip() else
                 DISCUSSION_PLACEHOLDER)
    parts.append(DISCUSSION_END)
    return "\n".join(parts).rstrip("\n") + "\n"


def write_atomic(path, text):
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp", dir=d)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def collect(runs_dir, status):
    results = {}
    for name, _closed, _what in SCENARIOS:
        for preset, strategy in COMBOS:
            rid = run_id(name, preset, strategy)
            summary, problem = read_summary(os.path.join(runs_dir, rid, "summary.json"))
            code, message = status.get(rid, (None, ""))
            if code is not None and code not in (0, 1):
                why = f"carril_sim exited {code}" + (f": {message}" if message else "")
                # A summary left over from an earlier run is not this run's result.
                summary, problem = None, why
            elif summary is not None and summary.get("scenario") not in (None, name):
                problem = f"summary.json names scenario {summary.get('scenario')!r}"
            results[rid] = {"summary": summary, "problem": problem}
    return results


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("matrix", help="print the runs, one '<scenario> <preset> <strategy>' a line")
    rep = sub.add_parser("report", help="write docs/experiments.md from the runs' summaries")
    rep.add_argument("--runs", required=True,
                     help="directory holding <scenario>_<preset>_<strategy>/")
    rep.add_argument("--status", help="exit codes of the runs, as tools/experiments.sh writes them")
    rep.add_argument("--img-dir", default=None, help="images directory (default: <out dir>/img)")
    rep.add_argument("--out", default=None, help="report file (default: docs/experiments.md)")
    args = ap.parse_args(argv)

    if args.cmd == "matrix":
        for name, _closed, _what in SCENARIOS:
            for preset, strategy in COMBOS:
                print(name, preset, strategy)
        return 0

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = args.out or os.path.join(root, "docs", "experiments.md")
    img_abs = args.img_dir or os.path.join(os.path.dirname(os.path.abspath(out)), "img")
    img_rel = os.path.relpath(img_abs, os.path.dirname(os.path.abspath(out))).replace(os.sep, "/")

    discussion = None
    try:
        with open(out, encoding="utf-8") as f:
            discussion = kept_discussion(f.read())
    except FileNotFoundError:
        pass
    except ValueError as e:
        print(f"experiments_report: {out}: {e}; not rewriting it (restore the marker "
              f"'{DISCUSSION_END}')", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"experiments_report: cannot read {out}: {e}", file=sys.stderr)
        return 2

    results = collect(args.runs, read_status(args.status))
    page = build_page(results, img_rel, img_abs, discussion)
    try:
        write_atomic(out, page)
    except OSError as e:
        print(f"experiments_report: cannot write {out}: {e}", file=sys.stderr)
        return 2
    with_output = sum(1 for r in results.values() if r["summary"] is not None)
    passed = sum(1 for r in results.values()
                 if r["summary"] is not None and r["summary"].get("passed") is True)
    print(f"experiments_report: wrote {out}: {len(results)} runs, {with_output} with a summary, "
          f"{passed} passed" + ("; discussion kept" if discussion is not None else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
