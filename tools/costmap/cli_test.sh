#!/usr/bin/env bash
# carril_costmap against large and interrupted runs (issue 46 item 9): a valid map too large for
# what is asked (a PNG at SCALE 16, a derive beyond the memory it may use) is refused with the
# figures before anything is allocated, never an abort; a derive killed at any moment (SIGTERM or
# SIGKILL) leaves the old map pair or the new one, never a mix, and after SIGTERM no temporary.
# Usage: cli_test.sh CARRIL_COSTMAP ROBOT.yaml
set -uo pipefail
tool=$1 robot=$2
d=$(mktemp -d "${TMPDIR:-/tmp}/carril_costmap_cli.XXXXXX")
trap 'rm -rf "$d"' EXIT
failures=0
check() {  # check OK WHAT
  if [ "$1" = 0 ]; then echo "ok    $2"; else echo "FAIL  $2"; failures=$((failures + 1)); fi
}

# A CARRILEM file of NX x NY cells at RES m, heights a gentle slope (docs/map-formats.md).
make_map() {
  python3 - "$@" <<'PY'
import struct, sys, zlib
path, nx, ny, res = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
head = b"CARRILEM" + struct.pack("<IdIIdd", 1, res, nx, ny, 0.0, 0.0)
head += b"odom".ljust(32, b"\0") + struct.pack("<Q", nx * ny)
row = b"".join(struct.pack("<ff", 0.001 * i, 0.0001) for i in range(nx))
body = head + row * ny
with open(path, "wb") as f:
    f.write(body + struct.pack("<I", zlib.crc32(body) & 0xFFFFFFFF))
PY
}

make_map "$d/big.carrilem" 2048 2048 0.05
out=$("$tool" heights "$d/big.carrilem" "$d/h.png" 16 2>&1); rc=$?
echo "heights x16: exit $rc: $out"
[ $rc -eq 1 ] && grep -q "2048 x 2048 cells at scale 16 is 32768 x 32768 pixels" <<<"$out"
check $? "heights at SCALE 16 of a 2048 x 2048 map: refused with the figures (exit 1)"
[ ! -e "$d/h.png" ]; check $? "heights: nothing written"

# 300 MiB of address space: the derive's grids for 4 M cells do not fit.
out=$( (ulimit -v 307200; "$tool" derive "$d/big.carrilem" "$robot" "$d/cm") 2>&1); rc=$?
echo "derive under ulimit -v 300 MiB: exit $rc: $out"
[ $rc -eq 1 ] && grep -q "derive: 2048 x 2048 cells need about" <<<"$out"
check $? "derive beyond the memory it may use: refused with the figures (exit 1, no abort)"
[ -z "$(ls "$d" | grep '^cm\|^\.cm')" ]; check $? "derive refused: nothing written"

# Two maps of different geometry; every derive of one replaces the pair of the other.
make_map "$d/a.carrilem" 900 700 0.05
make_map "$d/b.carrilem" 640 1000 0.1
"$tool" derive "$d/a.carrilem" "$robot" "$d/cm" >/dev/null || check 1 "first derive"
consistent() {  # the YAML's image exists and has that YAML's geometry
  python3 - "$d" <<'PY'
import os, re, sys
d = sys.argv[1]
yaml = open(os.path.join(d, "cm.yaml")).read()
image = re.search(r'^image: "([^"]+)"', yaml, re.M).group(1)
res = float(re.search(r"^resolution: (\S+)", yaml, re.M).group(1))
with open(os.path.join(d, image), "rb") as f:
    head = f.read(32).split(b"\n")
w, h = map(int, head[1].split())
want = (900, 700) if res == 0.05 else (640, 1000)
sys.exit(0 if (w, h) == want else 1)
PY
}
mixes=0 temps_after_term=0 kills=0
for k in $(seq 1 16); do
  src=$([ $((k % 2)) = 0 ] && echo a || echo b)
  sig=$([ $k -le 8 ] && echo TERM || echo KILL)
  "$tool" derive "$d/$src.carrilem" "$robot" "$d/cm" >/dev/null 2>&1 &
  pid=$!
  sleep "0.$(( (k * 37) % 5 ))$(( (k * 53) % 10 ))"
  kill -"$sig" "$pid" 2>/dev/null && kills=$((kills + 1))
  wait "$pid" 2>/dev/null
  consistent || mixes=$((mixes + 1))
  if [ "$sig" = TERM ] && ls -a "$d" | grep -q '\.tmp\.'; then temps_after_term=$((temps_after_term + 1)); fi
done
echo "16 derives interrupted ($kills signals delivered): $mixes mixed pairs, $temps_after_term with a temporary after SIGTERM"
[ $mixes -eq 0 ]; check $? "every interrupted derive left a whole pair (old or new)"
[ $temps_after_term -eq 0 ]; check $? "no temporary behind after SIGTERM"
"$tool" derive "$d/a.carrilem" "$robot" "$d/cm" >/dev/null && consistent && ! ls -a "$d" | grep -q '\.tmp\.'
check $? "the next complete derive: a whole pair and no temporary left (SIGKILL's cleaned up)"
n=$(ls "$d" | grep -c '^cm.*\.pgm$')
[ "$n" = 1 ]; check $? "one image beside cm.yaml ($n)"
echo "costmap cli: $failures failed"
[ $failures -eq 0 ]
