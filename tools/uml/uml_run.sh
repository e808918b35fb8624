#!/usr/bin/env bash
# Runs a command inside a real Linux kernel with SocketCAN: Debian's user-mode-linux boots as a
# process (about 3 s), with the host's / as its root (hostfs), loads can, can-raw, can-dev and
# vcan, creates vcan0..vcanN-1, runs COMMAND as root in the current directory with the current
# environment, then halts. COMMAND's stdout, stderr and exit code come back to the host.
# Exit 77 (CTest's skip) with a one-line reason when user-mode-linux cannot start at all.
#
# Usage: tools/uml/uml_run.sh [--vcan N] [--timeout S] [--mem SIZE] [--verbose] -- COMMAND ARGS...
#   --vcan N     virtual CAN interfaces vcan0..vcanN-1, up (default 1; 0: no CAN modules)
#   --timeout S  whole run, boot included [s] (default 300); then the kernel is killed, exit 124
#   --mem SIZE   guest memory (default 256M)
#   --verbose    print the kernel's console log after the run
# Environment: UML_LINUX (default /usr/bin/linux), UML_MODULES (default
# /usr/lib/uml/modules/<its version>).
set -uo pipefail

vcan=1 timeout_s=300 mem=256M verbose=0
usage() {
  sed -n '8,15s/^# \{0,1\}//p' "$0" >&2
  exit 2
}
while [ $# -gt 0 ]; do
  case $1 in
    --vcan) vcan=${2:?--vcan N}; shift 2 ;;
    --timeout) timeout_s=${2:?--timeout S}; shift 2 ;;
    --mem) mem=${2:?--mem SIZE}; shift 2 ;;
    --verbose) verbose=1; shift ;;
    --) shift; break ;;
    -h | --help) usage ;;
    *) echo "uml_run: unknown option '$1'" >&2; usage ;;
  esac
done
[ $# -gt 0 ] || usage
case $vcan in '' | *[!0-9]*) echo "uml_run: --vcan wants a count, got '$vcan'" >&2; exit 2 ;; esac

skip() {
  echo "uml_run: SKIP: $*" >&2
  exit 77
}

# AddressSanitizer's shadow memory does not fit a user-mode-linux process's address space (the
# guest aborts: "Shadow memory range interleaves with an existing memory mapping"): a command that
# would run a sanitized binary (the host-debug build) inside cannot run at all.
for arg in "$@"; do
  if [ -f "$arg" ] && [ -x "$arg" ] && readelf -d "$arg" 2>/dev/null | grep -q 'NEEDED.*libasan'; then
    skip "$arg is built with AddressSanitizer, which cannot run inside user-mode-linux"
  fi
done

linux=${UML_LINUX:-/usr/bin/linux}
[ -x "$linux" ] || skip "no user-mode-linux kernel at $linux (apt-get install user-mode-linux)"
ver=$(timeout 10 "$linux" --version 2>/dev/null | head -n 1)
[ -n "$ver" ] || skip "$linux --version printed nothing: not a user-mode-linux kernel?"
moddir=${UML_MODULES:-/usr/lib/uml/modules/$ver}
sbin_path=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
for tool in insmod ip halt; do
  PATH=$sbin_path command -v $tool >/dev/null ||
    skip "no $tool on this machine (apt-get install kmod iproute2)"
done

workroot=${TMPDIR:-/tmp}
work=$(mktemp -d "$workroot/uml_run.XXXXXX") || skip "cannot create a work directory in $workroot"
# UML's memory is a file it maps: on tmpfs (/dev/shm) it is fast; any writable directory works.
if [ -d /dev/shm ] && [ -w /dev/shm ]; then
  memdir=$(mktemp -d /dev/shm/uml_mem.XXXXXX) || memdir=$work/mem
else
  memdir=$work/mem
fi
mkdir -p "$memdir" "$work/umid" || skip "cannot create UML's memory directory $memdir"
uml_pid=
cleanup() {
  if [ -n "$uml_pid" ] && kill -0 "$uml_pid" 2>/dev/null; then
    kill -KILL -- "-$uml_pid" 2>/dev/null || kill -KILL "$uml_pid" 2>/dev/null
  fi
  rm -rf "$work" "$memdir"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The kernel modules, decompressed on the host when Debian ships them compressed.
mods=()
if [ "$vcan" -gt 0 ]; then
  [ -d "$moddir" ] || skip "no user-mode-linux modules in $moddir"
  for m in net/can/can net/can/can-raw drivers/net/can/dev/can-dev drivers/net/can/vcan; do
    f=
    for ext in ko ko.xz ko.zst ko.gz; do
      [ -f "$moddir/kernel/$m.$ext" ] && f=$moddir/kernel/$m.$ext && break
    done
    [ -n "$f" ] || skip "module $m missing in $moddir/kernel"
    case $f in
      *.xz) xz -dc "$f" >"$work/${m##*/}.ko" && f=$work/${m##*/}.ko ;;
      *.zst) zstd -qdc "$f" >"$work/${m##*/}.ko" && f=$work/${m##*/}.ko ;;
      *.gz) gzip -dc "$f" >"$work/${m##*/}.ko" && f=$work/${m##*/}.ko ;;
    esac
    mods+=("$f")
  done
fi

# What runs as the guest's init: the caller's environment and directory, then COMMAND.
export -p | grep -v -E '^declare -x (PWD|OLDPWD|SHLVL|_)=' >"$work/env"
{
  echo '#!/bin/bash'
  printf 'w=%q\n' "$work"
  echo ': >"$w/booted"'
  echo 'fail() { echo "$*" >"$w/setup_failed"; halt -f -p; exit 1; }'
  echo 'source "$w/env"'
  printf 'export PATH=%q:"$PATH"\n' "$sbin_path"
  echo 'mount -t proc proc /proc 2>/dev/null; mount -t sysfs sysfs /sys 2>/dev/null'
  # POSIX shared memory (shm_open) lives in /dev/shm: the guest's own tmpfs, not the host's.
  echo 'mkdir -p /dev/shm; mount -t tmpfs -o mode=1777 shm /dev/shm 2>"$w/mount.err" || fail "mount tmpfs on /dev/shm: $(cat "$w/mount.err")"'
  echo 'ip link set up lo'
  for f in "${mods[@]}"; do
    printf 'insmod %q 2>"$w/insmod.err" || fail "insmod %s: $(cat "$w/insmod.err")"\n' "$f" "$f"
  done
  for ((i = 0; i < vcan; i++)); do
    echo "ip link add dev vcan$i type vcan && ip link set up vcan$i || fail 'cannot create vcan$i'"
  done
  printf 'cd %q || fail "no directory %s inside the guest"\n' "$PWD" "$PWD"
  printf '%q ' "$@"
  echo '>"$w/stdout" 2>"$w/stderr" </dev/null'
  echo 'echo $? >"$w/rc"'
  echo 'sync; halt -f -p || poweroff -f || echo o >/proc/sysrq-trigger'
} >"$work/init"
chmod +x "$work/init"

# setsid: UML's helper processes share its process group, so a hang is killed whole. The
# shell's own stderr is muted meanwhile: it would report how the kernel process ended (it
# sometimes aborts while halting, after the command's results are written).
exec 3>&2 2>/dev/null
TMPDIR=$memdir setsid "$linux" mem="$mem" rootfstype=hostfs rootflags=/ rw init="$work/init" \
  uml_dir="$work/umid" con=null con0=fd:0,fd:1 quiet </dev/null >"$work/console" 2>&1 &
uml_pid=$!
deadline=$((SECONDS + timeout_s))
while kill -0 "$uml_pid" 2>/dev/null && [ $SECONDS -lt $deadline ]; do sleep 0.2; done
timed_out=0
if kill -0 "$uml_pid" 2>/dev/null; then
  timed_out=1
  kill -KILL -- "-$uml_pid" 2>/dev/null || kill -KILL "$uml_pid"
fi
wait "$uml_pid"
uml_pid=
exec 2>&3 3>&-

console_tail() { tail -n 15 "$work/console" | sed 's/^/  uml| /' >&2; }
[ $verbose -eq 1 ] && sed 's/^/  uml| /' "$work/console" >&2
if [ ! -e "$work/booted" ] && [ $timed_out -eq 0 ]; then
  reason=$(grep -v -E '^\s*$' "$work/console" | tail -n 1)
  skip "user-mode-linux did not start: ${reason:-no output} (kernel $linux, memory in $memdir)"
fi
[ -f "$work/stdout" ] && cat "$work/stdout"
[ -f "$work/stderr" ] && cat "$work/stderr" >&2
if [ $timed_out -eq 1 ]; then
  booted=$([ -e "$work/booted" ] && echo "the command was still running" || echo "before the guest booted")
  echo "uml_run: timed out after ${timeout_s} s, $booted: the kernel was killed; console:" >&2
  console_tail
  exit 124
fi
if [ -f "$work/setup_failed" ]; then
  echo "uml_run: guest setup failed: $(cat "$work/setup_failed")" >&2
  console_tail
  exit 1
fi
if [ ! -f "$work/rc" ]; then
  echo "uml_run: the command did not finish (the guest stopped early); console:" >&2
  console_tail
  exit 1
fi
exit "$(cat "$work/rc")"
