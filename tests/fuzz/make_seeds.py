#!/usr/bin/env python3
"""Writes the seed corpora of tests/fuzz/<target>/ (not regressions/, which holds found inputs):
copies of the shipped configuration files, and small valid inputs of the binary formats built
here, so that each seed is explained by this script. Run from anywhere; overwrites the seeds."""
import os
import shutil
import struct
import zlib
from pathlib import Path

FUZZ = Path(__file__).resolve().parent
ROOT = FUZZ.parents[1]


def put(target, name, data):
    d = FUZZ / target
    d.mkdir(exist_ok=True)
    (d / name).write_bytes(data if isinstance(data, bytes) else data.encode())


def copy_all(target, pattern):
    for f in sorted(ROOT.glob(pattern)):
        put(target, f.name, f.read_bytes())


# --- YAML files: the shipped ones are the valid examples.
copy_all("scenario", "scenarios/*.yaml")
copy_all("robot", "config/robots/*.yaml")
copy_all("mission", "config/missions/*.yaml")
copy_all("controller", "config/controller/*.yaml")
copy_all("tuning", "config/tuning/*.yaml")
copy_all("campaign", "scenarios/campaigns/*.yaml")

# --- Occupancy maps: YAML, the separator line, the PGM (fuzz_occupancy_map.cpp).
MAP_YAML = """image: map.pgm
resolution: 0.05
origin: [-0.2, -0.15, 0.0]
negate: {negate}
occupied_thresh: 0.65
free_thresh: 0.196
mode: trinary
"""
SEP = b"\n%%PGM%%\n"
W, H = 8, 6
pixels = bytes((0 if (x in (0, W - 1) or y in (0, H - 1)) else 254 if x < 5 else 205)
               for y in range(H) for x in range(W))
p5 = b"P5\n# carril fuzz seed\n%d %d\n255\n" % (W, H) + pixels
p2 = ("P2\n%d %d\n255\n" % (W, H) + "\n".join(
    " ".join(str(pixels[y * W + x]) for x in range(W)) for y in range(H)) + "\n").encode()
put("occupancy_map", "p5.bin", MAP_YAML.format(negate=0).encode() + SEP + p5)
put("occupancy_map", "p2_negate.bin", MAP_YAML.format(negate=1).encode() + SEP + p2)
put("occupancy_map", "maxval15.bin", MAP_YAML.format(negate=0).encode() + SEP +
    b"P5 4 2 15\n" + bytes([0, 15, 7, 15, 15, 15, 0, 3]))

# --- Elevation maps (loader/ElevationMapFile.hpp): header, cells, CRC-32 of both.


def elevation(nx, ny, frame=b"odom", res=0.1, ox=-1.0, oy=-0.5):
    head = b"CARRILEM" + struct.pack("<IdIIdd", 1, res, nx, ny, ox, oy)
    head += frame.ljust(32, b"\0") + struct.pack("<Q", nx * ny)
    assert len(head) == 84
    cells = b"".join(struct.pack("<ff", 0.01 * i, 0.0 if i % 3 == 0 else 0.0004)
                     for i in range(nx * ny))
    return head + cells + struct.pack("<I", zlib.crc32(head + cells))


put("elevation_map", "3x2.bin", elevation(3, 2))
put("elevation_map", "1x1_map.bin", elevation(1, 1, frame=b"map", res=0.05, ox=0.0, oy=0.0))
put("elevation_map", "8x4.bin", elevation(8, 4))

# --- CAN frames (FuzzFrames.hpp): id u32 (bit 31 extended, 30 remote, 29 error), len, 8 bytes.


def frame(cob, data=b"", ext=False, rtr=False, err=False):
    raw = cob | (ext << 31) | (rtr << 30) | (err << 29)
    return struct.pack("<IB", raw, len(data)) + data.ljust(8, b"\0")


NODE = 3
# fuzz_canopen_frames: the watched node, then (frame, time step u16 [ms]) pairs.
ms = lambda t: struct.pack("<H", t)
put("canopen_frames", "boot_and_run.bin", bytes([NODE]) +
    frame(0x700 + NODE, b"\x00") + ms(10) +                       # boot-up
    frame(0x700 + NODE, b"\x7f") + ms(50) +                       # pre-operational
    frame(0x180 + NODE, struct.pack("<Hi", 0x0250, 0)) + ms(10) +  # switch on disabled
    frame(0x180 + NODE, struct.pack("<Hi", 0x0231, 0)) + ms(10) +  # ready to switch on
    frame(0x180 + NODE, struct.pack("<Hi", 0x0233, 0)) + ms(10) +  # switched on
    frame(0x180 + NODE, struct.pack("<Hi", 0x0637, 4096)) + ms(10) +  # operation enabled
    frame(0x280 + NODE, struct.pack("<i", 2**31 - 10)) + ms(10) +
    frame(0x280 + NODE, struct.pack("<i", -2**31 + 10)) + ms(10) +  # the counter wraps
    frame(0x700 + NODE, b"\x05") + ms(500))                       # operational, then silence
put("canopen_frames", "emcy_fault.bin", bytes([NODE]) +
    frame(0x080 + NODE, struct.pack("<HB5s", 0x2310, 0x03, b"\x01\x02\x03\x04\x05")) + ms(1) +
    frame(0x180 + NODE, struct.pack("<Hi", 0x0218, 0)) + ms(10) +  # fault
    frame(0x080 + NODE, struct.pack("<HB5s", 0x0000, 0x00, b"")) + ms(1) +  # error reset
    frame(0x580 + NODE, struct.pack("<BHBI", 0x80, 0x6060, 0, 0x06090030)) + ms(1))
put("canopen_frames", "odd_frames.bin", bytes([NODE]) +
    frame(0x700 + NODE, b"\x05\x00") + ms(1) +   # heartbeat of the wrong length
    frame(0x700 + NODE, b"\x05", rtr=True) + ms(1) +
    frame(0x000, b"\x01\x00", err=True) + ms(1) +
    frame(0x18000000 + NODE, b"\x00" * 6, ext=True) + ms(1))

# fuzz_sdo_client: a script of steps (command byte, arguments).
DL, UL, RESP, ANY, TICK = 0, 1, 2, 3, 4


def sdo(cmd, index, sub, payload):
    return struct.pack("<BHBI", cmd, index, sub, payload)


def resp(data):
    return bytes([RESP]) + struct.pack("<IB", 0, 8) + data


start = bytes([NODE - 1])  # node id = byte % 127 + 1
put("sdo_client", "download_done.bin", start +
    bytes([DL]) + struct.pack("<HBIB", 0x6060, 0, 3, 1) + bytes([TICK]) + ms(1) +
    resp(sdo(0x60, 0x6060, 0, 0)))
put("sdo_client", "upload_values.bin", start +
    bytes([UL]) + struct.pack("<HB", 0x1000, 0) + bytes([TICK]) + ms(1) +
    resp(sdo(0x43, 0x1000, 0, 0x00020192)) +
    bytes([UL]) + struct.pack("<HB", 0x6061, 0) + resp(sdo(0x4F, 0x6061, 0, 3)) +
    bytes([UL]) + struct.pack("<HB", 0x1018, 1) + resp(sdo(0x42, 0x1018, 1, 0xFFFFFFFF)) +
    bytes([UL]) + struct.pack("<HB", 0x1008, 0) + resp(sdo(0x41, 0x1008, 0, 12)))  # segmented
put("sdo_client", "abort_and_timeout.bin", start +
    bytes([DL]) + struct.pack("<HBIB", 0x60FF, 0, 1000, 4) +
    resp(sdo(0x80, 0x60FF, 0, 0x06090030)) +
    bytes([DL]) + struct.pack("<HBIB", 0x6083, 0, 500, 4) +
    bytes([TICK]) + ms(1) + bytes([TICK]) + ms(20) + bytes([TICK]) + ms(40) +
    resp(sdo(0x60, 0x6084, 0, 0)) +  # late and for another object
    bytes([ANY]) + frame(0x580 + NODE, b"\x60\x83\x60\x00"))

# --- SCIP 2.0 (hal/scip/ScipCodec.hpp): the sensor's side of a session.


def sum6(s):
    return chr((sum(s.encode()) & 0x3F) + 0x30)


def line(s):
    return s + sum6(s) + "\n"


def info(key, value):
    return key + ":" + value + ";" + sum6(key + ":" + value) + "\n"


def enc(v, chars):
    return "".join(chr(((v >> (6 * (chars - 1 - i))) & 0x3F) + 0x30) for i in range(chars))


def data_lines(values, chars):
    s = "".join(enc(v, chars) for v in values)
    return "".join(line(s[i:i + 64]) for i in range(0, len(s), 64))


pp = ("PP\n" + line("00") + info("MODL", "UST-10LX") + info("DMIN", "20") + info("DMAX", "30000")
      + info("ARES", "1440") + info("AMIN", "0") + info("AMAX", "1080") + info("AFRT", "540")
      + info("SCAN", "2400") + "\n")
qt = "QT\n" + line("00") + "\n"
vv = ("VV\n" + line("00") + info("VEND", "Hokuyo Automatic Co., Ltd.") + info("PROD", "UST-10LX")
      + info("FIRM", "1.0") + info("PROT", "SCIP 2.0") + info("SERI", "H0000000") + "\n")
md_ack = "MD0000001001000\n" + line("00") + "\n"
ranges = [1000 + 10 * i for i in range(11)]
md_scan = "MD0000001001000\n" + line("99") + line(enc(123456, 4)) + data_lines(ranges, 3) + "\n"
gd = "GD0000003001\n" + line("00") + line(enc(77, 4)) + data_lines([0, 1, 2, 3], 3) + "\n"
me = ("ME0000000301000\n" + line("99") + line(enc(5, 4)) +
      data_lines([v for i in range(4) for v in (500 + i, 100 + i)], 3) + "\n")
err = "MD0000200001000\n" + line("05") + "\n"
put("scip_client", "session.txt", qt + pp + md_ack + md_scan + md_scan)
put("scip_client", "vv_gd.txt", vv + gd)
put("scip_client", "me_err.txt", "\n" + me + err)

# --- candump lines (hal/can/Candump.hpp).
put("candump", "std.txt", "(1436509052.249713) vcan0 44C#44A1\n")
put("candump", "ext.txt", "(0000000001.000001) can0 18DAF110#0011223344556677")
put("candump", "rtr.txt", "(1.000000) can1 123#R4")
put("candump", "err.txt", "(1700000000.5) can0 20000040#0000000000000000")
