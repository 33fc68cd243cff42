#!/usr/bin/env python3
"""The front-end's worst steps against a reference, with scan overlays to look at.

usage: frontend_worst.py LOG.log.gz REFERENCE.tum OURS.tum [ODOMETRY.tum] [--top 15]
                         [--png DIR] [--context 6] [--half 5]

Pairs consecutive poses k -> k+1 (matched by timestamp) and ranks the steps by how far our step
is from the reference's (translation, in the frame of pose k). With ODOMETRY (a dead-reckoning
run of the same log) each line also says whom the odometry, which shares no input with either,
is closer to. With --png, writes DIR/step_K.png per listed step: left the scans K-context..K+1
placed at the reference's poses, right at ours, both seen from pose K+1 (scan K+1 red, the
others grey, poses blue; 2 cm pixels, HALF metres around the robot), so a slide along a
corridor or a turned scan shows as doubled walls on one side.

Reads FLASER lines of CARMEN logs (plain or gzip), beams spread over 180 degrees.
"""
import gzip
import math
import os
import struct
import sys
import zlib

from tum2d import load, matched, relative, take_options


def read_scans(path):
    opener = gzip.open if path.endswith(".gz") else open
    scans = []
    with opener(path, "rt", errors="replace") as f:
        for line in f:
            if line.startswith("FLASER"):
                v = line.split()
                n = int(v[1])
                scans.append([float(x) for x in v[2:2 + n]])
    return scans


def scan_points(ranges, pose, max_range=20.0):
    n = len(ranges)
    # 180/360 beams: 1 or 0.5 degree steps starting at -90; 181/361: both ends included.
    step = math.pi / n if n in (180, 360) else math.pi / max(1, n - 1)
    c, s = math.cos(pose[3]), math.sin(pose[3])
    out = []
    for k, r in enumerate(ranges):
        if r <= 0.01 or r > max_range:
            continue
        a = -math.pi / 2 + step * k
        x, y = r * math.cos(a), r * math.sin(a)
        out.append((pose[1] + c * x - s * y, pose[2] + s * x + c * y))
    return out


def write_png(path, width, height, rgb):
    raw = b"".join(b"\x00" + bytes(rgb[y * width * 3:(y + 1) * width * 3]) for y in range(height))

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" +
                chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def panel(scans, traj, first, last, half, res):
    size = int(2 * half / res)
    rgb = bytearray([255]) * (size * size * 3)
    view = traj[last]
    c, s = math.cos(-view[3]), math.sin(-view[3])

    def put(x, y, colour):
        dx, dy = x - view[1], y - view[2]
        u, v = c * dx - s * dy, s * dx + c * dy
        px, py = int((u + half) / res), int((half - v) / res)
        if 0 <= px < size and 0 <= py < size:
            o = (py * size + px) * 3
            rgb[o:o + 3] = bytes(colour)

    for k in range(first, last):
        for x, y in scan_points(scans[k], traj[k]):
            put(x, y, (130, 130, 130))
    for x, y in scan_points(scans[last], traj[last]):
        put(x, y, (220, 0, 0))
    for k in range(first, last + 1):
        put(traj[k][1], traj[k][2], (0, 0, 255))
    return rgb, size


def main():
    args = sys.argv[1:]
    opts = take_options(args, {"--top": 15, "--png": "", "--context": 6, "--half": 5.0})
    if len(args) not in (3, 4):
        print(__doc__, file=sys.stderr)
        return 2
    log = args[0]
    trajs = [load(p) for p in args[1:]]
    rows = matched(trajs)  # (index in the reference = scan index, poses...)
    steps = []
    for a, b in zip(rows, rows[1:]):
        if b[0] != a[0] + 1:
            continue
        m = [relative(a[1][e], b[1][e]) for e in range(len(trajs))]
        d = math.hypot(m[1][0] - m[0][0], m[1][1] - m[0][1])
        line = "step %5d -> %5d: ours - reference %5.1f cm, %5.2f deg; reference step %.2f m, %+.1f deg" % (
            a[0], b[0], 100 * d, math.degrees(math.remainder(m[1][2] - m[0][2], 2 * math.pi)),
            math.hypot(m[0][0], m[0][1]), math.degrees(m[0][2]))
        if len(trajs) == 3:
            to_ours = math.hypot(m[2][0] - m[1][0], m[2][1] - m[1][1])
            to_ref = math.hypot(m[2][0] - m[0][0], m[2][1] - m[0][1])
            line += "; odometry %.1f cm from ours, %.1f cm from the reference" % (100 * to_ours,
                                                                               100 * to_ref)
        steps.append((d, a[0], line))
    steps.sort(reverse=True)
    listed = steps[:opts["--top"]]
    for _, _, line in listed:
        print(line)
    if opts["--png"]:
        os.makedirs(opts["--png"], exist_ok=True)
        scans = read_scans(log)
        ref = trajs[0]
        ours_by_index = {}
        for i, poses in rows:
            ours_by_index[i] = poses[1]
        if len(scans) != len(ref):
            print("frontend_worst.py: %d scans in the log, %d reference poses; no PNGs" %
                  (len(scans), len(ref)), file=sys.stderr)
            return 1
        ours = [ours_by_index.get(i, ref[i]) for i in range(len(ref))]
        res = 0.02
        for _, k, _ in listed:
            first = max(0, k - opts["--context"])
            left, size = panel(scans, ref, first, k + 1, opts["--half"], res)
            right, _ = panel(scans, ours, first, k + 1, opts["--half"], res)
            gap = 4
            width = 2 * size + gap
            rgb = bytearray(width * size * 3)
            for y in range(size):
                rgb[y * width * 3:y * width * 3 + size * 3] = left[y * size * 3:(y + 1) * size * 3]
                o = y * width * 3 + (size + gap) * 3
                rgb[o:o + size * 3] = right[y * size * 3:(y + 1) * size * 3]
            write_png(os.path.join(opts["--png"], "step_%d.png" % k), width, size, rgb)
    return 0


if __name__ == "__main__":
    sys.exit(main())
