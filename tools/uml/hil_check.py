#!/usr/bin/env python3
"""Checks what tools/uml/hil_inside.sh captured (issue 9 item 8) and prints the figures.

Run A: one full lap through CiA 402 over vcan0; the PDO rate from the candump capture; after
drive 1 (node 2) stops its heartbeat, FAULT and every wheel commanded to quick stop within 3
heartbeat periods of its last heartbeat, and standing still after. Run B: after carril_controller
is killed with SIGKILL, the emulated drives stop on their own.
Usage: hil_check.py OUT_DIR HEARTBEAT_MS. Exit 0 when every check passes, 1 otherwise."""
import json
import re
import sys

out, hb_ms = sys.argv[1], float(sys.argv[2])
failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def candump(path):
    """(t [s], id, data bytes) per line of `candump -L`: "(1700000000.123456) vcan0 181#0F06..."."""
    frames = []
    for line in open(path):
        m = re.match(r"\((\d+\.\d+)\) \S+ ([0-9A-Fa-f]+)#([0-9A-Fa-f]*)", line)
        if m:
            frames.append((float(m.group(1)), int(m.group(2), 16), bytes.fromhex(m.group(3))))
    return frames


def summary(name):
    path = f"{out}/{name}/hil_summary.json"
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        # The simulator did not finish its run (its log is shown after this): say which file.
        print(f"FAIL  run {name.upper()}: no summary from the simulator: {path}: {e}")
        sys.exit(1)


# Each phase of hil_inside.sh has its own bound: one that ran over is named first.
try:
    for line in open(f"{out}/exits"):
        if line.startswith("phase_timeout "):
            check(False, "phase ran over: " + line[len("phase_timeout "):].strip())
        elif line.startswith("retry "):
            print("note  " + line.strip())  # a bring-up refused on a starved guest, then retried
except OSError as e:
    check(False, f"hil_inside.sh left no exits file: {e}")

# Run A.
a = summary("a")
fa = candump(f"{out}/a.candump")
# candump -d: "DROPCOUNT: dropped N CAN frame(s) on 'vcan0' socket (total drops T)".
try:
    drops = [int(m.group(1)) for m in
             (re.search(r"total drops (\d+)", line) for line in open(f"{out}/a.candump")) if m]
except OSError:
    drops = []
print(f"run A: candump dropped {drops[-1] if drops else 0} frames of the capture")
print(f"run A: {len(fa)} frames captured, laps {a['laps']}, progress {a['progress']:.3f}, "
      f"collisions {a['collisions']}, SYNC {a['sync_rate_hz']:.1f} Hz, TPDO {a['tpdo_rate_hz']:.1f} /s")
check(a["laps"] >= 1, f"run A: at least one full lap of the circle over vcan0 (laps {a['laps']})")
check(a["collisions"] == 0, f"run A: no collision ({a['collisions']})")
syncs = [t for t, i, _ in fa if i == 0x080]
check(len(syncs) > 100, f"run A: SYNCs captured ({len(syncs)})")
inj_t = None
silent_node = 2  # wheel index 1
hb = [t for t, i, _ in fa if i == 0x700 + silent_node]
# The silence: the last heartbeat of node 2 is followed by a gap far longer than its period.
gaps = [(hb[k + 1] - hb[k], hb[k]) for k in range(len(hb) - 1)]
last_hb = max((t for g, t in gaps if g > 10 * hb_ms / 1000.0), default=hb[-1] if hb else None)
if hb and (not gaps or max(g for g, _ in gaps) <= 10 * hb_ms / 1000.0):
    last_hb = hb[-1]
if syncs and last_hb is not None:
    # The PDO rate while the robot drove: from the first SYNC to the silence.
    t0, t1 = syncs[0], last_hb
    for node in range(1, 5):
        n1 = sum(1 for t, i, _ in fa if i == 0x180 + node and t0 <= t <= t1)
        n2 = sum(1 for t, i, _ in fa if i == 0x280 + node and t0 <= t <= t1)
        rate1, rate2 = n1 / (t1 - t0), n2 / (t1 - t0)
        print(f"run A: node {node}: TPDO1 {rate1:.1f} /s, TPDO2 {rate2:.1f} /s over {t1 - t0:.1f} s")
        check(rate1 >= 90.0 and rate2 >= 90.0,
              f"run A: node {node} PDO rate from the capture at least 90 /s at 100 Hz SYNC")
    nsync = sum(1 for t in syncs if t0 <= t <= t1)
    print(f"run A: SYNC {nsync / (t1 - t0):.1f} Hz from the capture")
    # After the last heartbeat: the first period whose RPDO1s to every node carry quick stop
    # (controlword 0x0002) and target 0.
    stop_t = None
    for t, i, d in fa:
        if t <= last_hb or not (0x201 <= i <= 0x204) or len(d) != 6:
            continue
        cw = d[0] | (d[1] << 8)
        if cw & 0x000F == 0x0002:
            later = [x for x in fa if x[0] >= t and 0x201 <= x[1] <= 0x204 and len(x[2]) == 6]
            nodes = set()
            for x in later[:8]:
                if (x[2][0] | (x[2][1] << 8)) & 0x000F == 0x0002:
                    nodes.add(x[1])
            if len(nodes) == 4:
                stop_t = t
                break
    if stop_t is None:
        check(False, "run A: quick stop sent to every drive after the heartbeat loss")
    else:
        dt_ms = (stop_t - last_hb) * 1000.0
        print(f"run A: node 2's last heartbeat, then quick stop to all 4 drives after {dt_ms:.0f} ms "
              f"(3 heartbeat periods = {3 * hb_ms:.0f} ms)")
        check(dt_ms <= 3 * hb_ms, "run A: every wheel commanded to stop within 3 heartbeat periods")
inj = [x for x in a["injections"] if "heartbeat_silence" in x["what"]]
check(bool(inj) and inj[0]["applied"], "run A: the heartbeat silence was injected")
if inj:
    s = inj[0]["stopped_after_s"]
    print(f"run A: every emulated wheel below 0.01 rad/s {s:.3f} s after the silence began")
    check(0.0 <= s <= 3 * hb_ms / 1000.0 + 0.3,
          "run A: wheels standing still within 3 heartbeat periods plus the quick-stop ramp")
ctl_a = open(f"{out}/a.ctl.txt").read()
check("fault drive_fault" in ctl_a, "run A: carril_controller latched drive_fault")
m = re.search(r"canopen: last fault: (.*)", ctl_a)
print("run A: controller: " + (m.group(1) if m else "(no last fault line)"))
# The fault that stopped the robot is node 2's (the quick stop above follows its last heartbeat);
# last_fault() is the newest one, which may be a later loss of another node while stopped.
check(bool(m) and "heartbeat lost" in m.group(1), "run A: the controller names a heartbeat loss")

# Both binaries' --can-log files: candump log lines, renamed from FILE.part when complete.
def log_lines(path):
    """Lines and malformed lines. A FILE.part left by a killed writer may end in a torn last line
    (that is why it was never renamed): that one line is not counted against it."""
    lines = open(path).read().split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    elif path.endswith(".part") and lines:
        lines.pop()  # the torn last line of a killed writer
    bad = sum(1 for line in lines
              if not re.match(r"\(\d+\.\d{6}\) vcan0 [0-9A-F]{3,8}#[0-9A-F]*$", line))
    return len(lines), bad


for path in (f"{out}/b.sim.canlog", f"{out}/b.ctl.canlog.part"):
    try:
        n, bad = log_lines(path)
        print(f"{path.split('/')[-1]}: {n} candump lines, {bad} malformed")
        check(n > 1000 and bad == 0, f"--can-log {path.split('/')[-1]}: candump log lines")
    except OSError as e:
        check(False, f"--can-log {path}: {e}")

# Run B.
b = summary("b")
exits = open(f"{out}/exits").read()
check("killed_b" in exits, "run B: carril_controller was killed with SIGKILL while following")
lost = [d["master_heartbeat_lost"] for d in b["drives"]]
stop_s = b["stopped_after_controller_lost_s"]
print(f"run B: drives that saw the controller's heartbeat lost: {sum(lost)} of {len(lost)}; every "
      f"wheel still {stop_s:.3f} s after the first saw it; states "
      + ", ".join(d["state"] for d in b["drives"]))
check(all(lost), "run B: every drive saw the controller's heartbeat lost")
check(0.0 <= stop_s <= 0.5, "run B: the drives stopped on their own (within 0.5 s of noticing)")
check(all(abs(d["wheel_radps"]) < 0.01 for d in b["drives"]), "run B: every wheel at rest at the end")

# Run C: every catchable stopping signal ends in a quick stop to each drive, then NMT stop.
for sig in ("INT", "TERM", "HUP"):
    try:
        frames = candump(f"{out}/c_{sig}.ctl.canlog")
        report = open(f"{out}/c_{sig}.ctl.txt").read()
    except OSError as e:
        check(False, f"run C: SIG{sig}: {e}")
        continue
    nmt_stop = [k for k, f in enumerate(frames) if f[1] == 0x000 and f[2][:1] == b"\x02"]
    last = nmt_stop[-1] if nmt_stop else len(frames)
    quick = {f[1] - 0x200 for f in frames[max(0, last - 40):last]
             if 0x201 <= f[1] <= 0x204 and f[2][:2] == b"\x02\x00"}
    print(f"run C: SIG{sig}: {len(frames)} frames logged; quick stop to nodes {sorted(quick)} "
          f"before NMT stop: {bool(nmt_stop)}")
    check(f"stopped by a signal (SIG{sig})" in report, f"run C: SIG{sig}: the report names it")
    check(quick == {1, 2, 3, 4} and bool(nmt_stop),
          f"run C: SIG{sig}: quick stop to all 4 drives, then NMT stop, on the bus")

print(f"hil_check: {len(failures)} failed")
sys.exit(1 if failures else 0)
