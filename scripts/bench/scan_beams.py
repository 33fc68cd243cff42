#!/usr/bin/env python3
"""Beams per scan of a log's first laser scan, for the benchmark tables.

usage: scan_beams.py LOG [TOPIC]
CARMEN logs (plain or .gz): the reading count of the first FLASER / ROBOTLASER1 line.
ROS1 bags (v2.0, chunks uncompressed or bz2): the ranges length of the first
sensor_msgs/LaserScan on TOPIC (default: the first LaserScan topic).
Prints the number, or an error on stderr with exit status 1.
"""
import bz2
import gzip
import struct
import sys


def carmen_beams(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt", errors="replace") as f:
        for line in f:
            fields = line.split()
            if fields and fields[0] == "FLASER":
                return int(fields[1])
            if fields and fields[0] == "ROBOTLASER1":
                return int(fields[8])  # type start_angle fov resolution max_range accuracy mode n
    raise ValueError("no FLASER or ROBOTLASER1 line")


def bag_records(data):
    """Yields (header fields, payload) of the records in a bag byte string."""
    i = 0
    while i + 4 <= len(data):
        (hlen,) = struct.unpack_from("<I", data, i)
        i += 4
        header, j = {}, i
        while j < i + hlen:
            (n,) = struct.unpack_from("<I", data, j)
            key, value = data[j + 4:j + 4 + n].split(b"=", 1)
            header[key] = value
            j += 4 + n
        i += hlen
        (dlen,) = struct.unpack_from("<I", data, i)
        i += 4
        yield header, data[i:i + dlen]
        i += dlen


def laser_scan_ranges(msg):
    """Length of ranges[] in a serialized sensor_msgs/LaserScan."""
    (frame_len,) = struct.unpack_from("<I", msg, 12)  # after seq, stamp.sec, stamp.nsec
    offset = 16 + frame_len + 7 * 4  # angle_min .. range_max are 7 float32
    return struct.unpack_from("<I", msg, offset)[0]


def bag_beams(path, topic):
    with open(path, "rb") as f:
        if f.readline() != b"#ROSBAG V2.0\n":
            raise ValueError("not a ROS1 bag v2.0")
        body = f.read()
    scans = set()
    for header, payload in bag_records(body):
        if header.get(b"op") != b"\x05":  # chunk
            continue
        compression = header.get(b"compression", b"none")
        if compression == b"bz2":
            payload = bz2.decompress(payload)
        elif compression != b"none":
            raise ValueError("chunk compression %s not supported here" % compression.decode())
        for h, data in bag_records(payload):
            op = h.get(b"op")
            if op == b"\x07":  # connection: its data is the connection header
                fields = dict(bag_records_fields(data))
                if fields.get(b"type") == b"sensor_msgs/LaserScan" and (
                        topic is None or h.get(b"topic", b"").decode() == topic):
                    scans.add(h[b"conn"])
            elif op == b"\x02" and h.get(b"conn") in scans:
                return laser_scan_ranges(data)
    raise ValueError("no sensor_msgs/LaserScan message" + (" on " + topic if topic else ""))


def bag_records_fields(data):
    j = 0
    while j < len(data):
        (n,) = struct.unpack_from("<I", data, j)
        key, value = data[j + 4:j + 4 + n].split(b"=", 1)
        yield key, value
        j += 4 + n


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    path = sys.argv[1]
    try:
        if path.endswith(".bag"):
            print(bag_beams(path, sys.argv[2] if len(sys.argv) > 2 else None))
        else:
            print(carmen_beams(path))
    except (OSError, ValueError, struct.error) as e:
        print("scan_beams.py: %s: %s" % (path, e), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
