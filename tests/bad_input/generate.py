#!/usr/bin/env python3
"""Writes the bad-input corpus: base/ (valid configs and references the cases run against),
cases/ (one small file per fault) and cases.yaml (command, expected exit code, message pattern).

Run from anywhere: python3 tests/bad_input/generate.py. The output is committed; rerun after
editing the table below. Binary files (ROS bags, archives, gzip, PGM) are crafted byte by byte.
"""
import gzip
import math
import os
import shutil
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = os.path.join(HERE, "cases")
BASE = os.path.join(HERE, "base")

# ---- helpers ---------------------------------------------------------------------------------


def write(folder, name, data):
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, name)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path, mode) as f:
        f.write(data)
    assert os.path.getsize(path) < 20 * 1024, name


def garbage(n, seed):
    # A fixed LCG so the corpus is reproducible byte for byte.
    out = bytearray()
    x = seed
    for _ in range(n):
        x = (x * 1103515245 + 12345) & 0x7FFFFFFF
        out.append((x >> 16) & 0xFF)
    return bytes(out)


# ---- CARMEN ----------------------------------------------------------------------------------


def flaser(ranges, t, x=0.0):
    r = " ".join(str(v) for v in ranges)
    return f"FLASER {len(ranges)} {r} {x} 0 0 {x} 0 0 {t:.6f} host {t:.6f}\n"


def odom(t, x=0.0):
    return f"ODOM {x} 0 0 0.1 0 0 {t:.6f} host {t:.6f}\n"


def carmen_log(n=12, ranges=None):
    text = ""
    for i in range(n):
        t = 100.0 + 0.1 * i
        text += odom(t - 0.01, 0.05 * i)
        text += flaser(ranges or [2.0 + 0.01 * k for k in range(30)], t, 0.05 * i)
    return text


# ---- ROS bag v2.0 ----------------------------------------------------------------------------


def u32(v):
    return struct.pack("<I", v & 0xFFFFFFFF)


def u64(v):
    return struct.pack("<Q", v)


def rstr(b):
    return u32(len(b)) + b


def field(name, value):
    return rstr(name.encode() + b"=" + value)


def record(header, data):
    return rstr(header) + rstr(data)


def op(o):
    return field("op", bytes([o]))


MD5 = {"sensor_msgs/LaserScan": "90c7ef2dc6895d81024acba2ac42f369",
       "nav_msgs/Odometry": "cd5e73d190d741a2f92e81eda573aca7"}


def connection(cid, topic, typ, md5=None):
    md5 = md5 or MD5.get(typ, "0" * 32)
    return record(op(7) + field("conn", u32(cid)) + field("topic", topic.encode()),
                  field("topic", topic.encode()) + field("type", typ.encode()) +
                  field("md5sum", md5.encode()) + field("message_definition", b"..."))


def message(cid, sec, nsec, data):
    return record(op(2) + field("conn", u32(cid)) + field("time", u32(sec) + u32(nsec)), data)


def ros_header(seq, sec, frame):
    return u32(seq) + u32(sec) + u32(500) + rstr(frame.encode())


def laser_scan(seq, sec, ranges, count=None):
    beams = len(ranges)
    s = ros_header(seq, sec, "/laser_frame")
    s += struct.pack("<7f", -1.5, 1.5, 3.0 / max(beams - 1, 1), 0.001, 0.1, 0.1, 30.0)
    s += u32(beams if count is None else count)
    s += b"".join(struct.pack("<f", r) for r in ranges)
    s += u32(0)
    return s


def odometry_msg(seq, sec, x):
    s = ros_header(seq, sec, "/odom") + rstr(b"/base_link")
    s += struct.pack("<3d", x, 0.0, 0.0) + struct.pack("<4d", 0, 0, 0, 1)
    s += struct.pack("<36d", *([0.01] + [0.0] * 35))
    s += struct.pack("<6d", 0.3, 0, 0, 0, 0, 0.1) + struct.pack("<36d", *([0.0] * 36))
    return s


def chunk(inner, how="none", payload=None, size=None):
    return record(op(5) + field("compression", how.encode()) +
                  field("size", u32(len(inner) if size is None else size)),
                  inner if payload is None else payload)


def bag_header():
    return record(op(3) + field("index_pos", u64(0)) + field("conn_count", u32(0)) +
                  field("chunk_count", u32(0)), b" " * 64)


MAGIC = b"#ROSBAG V2.0\n"


def scan_inner(n=5, ranges=None, t0=10, step=1, scan_type="sensor_msgs/LaserScan"):
    inner = connection(0, "/scan", scan_type) + connection(1, "/odom", "nav_msgs/Odometry")
    for i in range(n):
        sec = t0 + step * i
        inner += message(1, sec, 0, odometry_msg(i, sec, 0.1 * i))
        inner += message(0, sec, 1000, laser_scan(i, sec, ranges or [1.0 + 0.1 * k for k in range(20)]))
    return inner


def bag(*chunks):
    return MAGIC + bag_header() + b"".join(chunks)


# ---- binary archive (sdk/src/serialization/binary_archive.cpp) --------------------------------


def varint(v):
    out = bytearray()
    while True:
        b = v & 0x7F
        v >>= 7
        if v:
            out.append(b | 0x80)
        else:
            out.append(b)
            return bytes(out)


def a_str(s):
    return bytes([6]) + varint(len(s)) + s.encode()


def a_double(d):
    return bytes([5]) + struct.pack("<d", d)


def a_object(fields):
    out = bytes([9]) + u32(len(fields))
    for k, v in fields:
        out += varint(len(k)) + k.encode() + v
    return out


def archive(payload, version=1, length=None, crc=None):
    return (b"PLSB" + u32(version) + u64(len(payload) if length is None else length) +
            u32(zlib.crc32(payload) if crc is None else crc) + payload)


def prop(tag, value):
    return a_object([("type", a_str(tag)), ("value", value)])


# ---- PGM -------------------------------------------------------------------------------------


def pgm_p5(w, h, pixels, maxval=255):
    return f"P5\n{w} {h}\n{maxval}\n".encode() + pixels


# ---- camera datasets (PNG, JPEG, KITTI / EuRoC / TUM layouts) -------------------------------


def png_image(w, h, pixels, channels=1, bits=8):
    """pixels: w*h*channels sample values (row-major)."""
    color_type = {1: 0, 3: 2}[channels]
    rows = b""
    step = w * channels
    for y in range(h):
        row = pixels[y * step:(y + 1) * step]
        rows += b"\x00" + (bytes(row) if bits == 8 else b"".join(struct.pack(">H", v) for v in row))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", w, h, bits, color_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(rows)) +
            chunk(b"IEND", b""))


def grey_png(w=8, h=8, seed=0):
    return png_image(w, h, [(x * 7 + y * 13 + seed * 29) & 255 for y in range(h) for x in range(w)])


def depth_png(w=8, h=8, value=5000):
    return png_image(w, h, [value] * (w * h), 1, 16)


def grey_jpeg(w=8, h=8):
    """A baseline grey JPEG of flat mid-grey, built from its markers: one quantisation table,
    one-code Huffman tables (DC category 0 and AC end-of-block are both the 1-bit code 0), so
    every 8x8 block is two 0 bits."""
    def seg(marker, data):
        return bytes([0xFF, marker]) + struct.pack(">H", len(data) + 2) + data
    dqt = seg(0xDB, b"\x00" + b"\x01" * 64)
    sof = seg(0xC0, b"\x08" + struct.pack(">HH", h, w) + b"\x01" + b"\x01\x11\x00")
    one_code = b"\x01" + b"\x00" * 15 + b"\x00"  # one code of length 1, value 0
    dht = seg(0xC4, b"\x00" + one_code + b"\x10" + one_code)
    sos = seg(0xDA, b"\x01\x01\x00\x00\x3f\x00")
    blocks = ((w + 7) // 8) * ((h + 7) // 8)
    bits = "00" * blocks
    bits += "1" * (-len(bits) % 8)
    data = bytes(int(bits[i:i + 8], 2) for i in range(0, len(bits), 8))
    return b"\xff\xd8" + dqt + sof + dht + sos + data + b"\xff\xd9"


KITTI_CALIB = ("P0: 700 0 4 0 0 700 4 0 0 0 1 0\n"
               "P1: 700 0 4 -350 0 700 4 0 0 0 1 0\n")


def kitti_folder(n=2):
    files = {"calib.txt": KITTI_CALIB, "times.txt": "".join(f"{0.1 * i:.6f}\n" for i in range(n))}
    for i in range(n):
        files[f"image_0/{i:06d}.png"] = grey_png(seed=i)
        files[f"image_1/{i:06d}.png"] = grey_png(seed=i + 1)
    return files


def euroc_sensor(tx, drop=None):
    keys = [("sensor_type", "camera"),
            ("T_BS", f"\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, {tx}, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]"),
            ("resolution", "[8, 8]"), ("camera_model", "pinhole"),
            ("intrinsics", "[450.0, 450.0, 4.0, 4.0]"), ("distortion_model", "radial-tangential"),
            ("distortion_coefficients", "[-0.28, 0.07, 0.0002, 0.00002]")]
    return "%YAML:1.0\n" + "".join(f"{k}: {v}\n" for k, v in keys if k != drop)


def euroc_folder(n=2):
    files = {}
    for cam, tx in (("cam0", -0.02), ("cam1", 0.09)):
        files[f"mav0/{cam}/sensor.yaml"] = euroc_sensor(tx)
        rows = "#timestamp [ns],filename\n"
        for i in range(n):
            t = 1403715273262142976 + 50000000 * i
            rows += f"{t},{t}.png\n"
            files[f"mav0/{cam}/data/{t}.png"] = grey_png(seed=i)
        files[f"mav0/{cam}/data.csv"] = rows
    return files


def tum_folder(n=2, colour=".png"):
    files = {"rgb.txt": "# colour\n", "depth.txt": "# depth\n"}
    for i in range(n):
        t = f"{1.0 + i / 30:.6f}"
        files["rgb.txt"] += f"{t} rgb/{t}{colour}\n"
        files["depth.txt"] += f"{t} depth/{t}.png\n"
        files[f"rgb/{t}{colour}"] = grey_png(seed=i) if colour == ".png" else grey_jpeg()
        files[f"depth/{t}.png"] = depth_png()
    return files


def rgbd_folder(n=2):
    files = {"pose.txt": "".join(f"{0.01 * i} 0 0 0 0 0 1\n" for i in range(n))}
    for i in range(1, n + 1):
        files[f"color/{i}.png"] = grey_png(seed=i)
        files[f"depth/{i}.png"] = depth_png()
    return files


# ---- the cases -------------------------------------------------------------------------------

cases = []


def case(name, content, command, exit_code, pattern, why, binary=None, ext=None):
    """content None = the file does not exist (missing-file cases); a dict = a folder of files
    (relative path -> content), for the camera dataset layouts."""
    entry = {"name": name, "command": command, "exit": exit_code, "pattern": pattern, "why": why}
    if isinstance(content, dict):
        shutil.rmtree(os.path.join(CASES, name), ignore_errors=True)
        for rel, data in sorted(content.items()):
            write(os.path.join(CASES, name, os.path.dirname(rel)), os.path.basename(rel), data)
        entry["file"] = "cases/" + name
    elif content is not None:
        fname = name + (ext or "")
        write(CASES, fname, content)
        entry["file"] = "cases/" + fname
    else:
        entry["file"] = "cases/" + name + (ext or "")
        entry["missing"] = True
    if binary:
        entry["binary"] = binary
    cases.append(entry)


VALIDATE = "validate {file}"
CARMEN = "run {dir}/base/carmen_run.yaml -o {tmp}/out --set source.path={file}"
ROSBAG = "run {dir}/base/rosbag_run.yaml -o {tmp}/out --set source.path={file}"
WORLD = "validate {dir}/base/sim_world.yaml --set source.world={file}"
KITTI = "run {dir}/base/kitti_run.yaml -o {tmp}/out --set source.path={file}"
KITTI_RAW = "run {dir}/base/kitti_raw_run.yaml -o {tmp}/out --set source.path={file}"
EUROC = "run {dir}/base/euroc_run.yaml -o {tmp}/out --set source.path={file}"
TUM = "run {dir}/base/tum_run.yaml -o {tmp}/out --set source.path={file}"
RGBD_FOLDER = "run {dir}/base/rgbd_folder_run.yaml -o {tmp}/out --set source.path={file}"
ATE_TUM = "eval ate {dir}/base/ref.tum {file}"
ATE_KITTI = "eval ate {dir}/base/ref.kitti {file}"
GRAPH = "graph {file}"
ARCHIVE = "archive {file}"

# The pipeline is the odometry-only one that tests/io_odometry runs too (its comments left out).
with open(os.path.join(HERE, "..", "support", "odometry_only.yaml")) as f:
    ODOMETRY_ONLY = "".join(line for line in f if not line.startswith("#"))
GOOD_CONFIG = """plugins: [sim, odometry]
source: {type: sim.Simulator2D, session: stage-0, lasers: [front_laser]}
""" + ODOMETRY_ONLY

# Base files (valid).
write(BASE, "good.yaml", GOOD_CONFIG)
write(BASE, "carmen_run.yaml", GOOD_CONFIG.replace("[sim, odometry]", "[io, odometry]").replace(
    "{type: sim.Simulator2D, session: stage-0, lasers: [front_laser]}",
    "{type: io.CarmenSource, path: set-by-the-case}") +
    "outputs:\n  - {type: io.TrajectoryWriter, file: traj.tum, format: tum}\n")
write(BASE, "rosbag_run.yaml", GOOD_CONFIG.replace("[sim, odometry]", "[io, odometry]").replace(
    "{type: sim.Simulator2D, session: stage-0, lasers: [front_laser]}",
    "{type: io.RosbagSource, path: set-by-the-case}") +
    "outputs:\n  - {type: io.TrajectoryWriter, file: traj.tum, format: tum}\n")
write(BASE, "sim_world.yaml", GOOD_CONFIG.replace(
    "session: stage-0, ", "world: set-by-the-case, start: [1.0, 1.0], "))
# Camera sources: read every frame, write the reference trajectory (no tracker needed).
CAMERA_RUN = """plugins: [io]
source: {type: io.SOURCE, path: set-by-the-case}
outputs:
  - {type: io.TrajectoryWriter, trajectory: reference, format: tum, file: reference.tum}
"""
write(BASE, "kitti_run.yaml", CAMERA_RUN.replace("SOURCE", "KittiSource"))
write(BASE, "kitti_raw_run.yaml", CAMERA_RUN.replace("SOURCE", "KittiRawSource"))
write(BASE, "euroc_run.yaml", CAMERA_RUN.replace("SOURCE", "EurocSource"))
write(BASE, "tum_run.yaml", CAMERA_RUN.replace("SOURCE", "TumRgbdSource").replace(
    "path: set-by-the-case", "path: set-by-the-case, fx: 500, fy: 500, cx: 4, cy: 4"))
write(BASE, "rgbd_folder_run.yaml", CAMERA_RUN.replace("SOURCE", "RgbdFolderSource").replace(
    "path: set-by-the-case", "path: set-by-the-case, fx: 500, fy: 500, cx: 4, cy: 4"))
write(BASE, "ref.tum", "".join(f"{i:.1f} {0.1*i} 0 0 0 0 0 1\n" for i in range(20)))
write(BASE, "ref.kitti", "".join(f"1 0 0 {0.1*i} 0 1 0 0 0 0 1 0\n" for i in range(20)))
write(BASE, "good.log", carmen_log())
write(BASE, "good.bag", bag(chunk(scan_inner())))
write(BASE, "good.g2o", "".join(f"VERTEX_SE2 {i} {i}.0 0 0\n" for i in range(5)) +
      "".join(f"EDGE_SE2 {i} {i+1} 1 0 0 500 0 0 500 0 5000\n" for i in range(4)) + "FIX 0\n")
write(BASE, "good.toro", "".join(f"VERTEX2 {i} {i}.0 0 0\n" for i in range(5)) +
      "".join(f"EDGE2 {i} {i+1} 1 0 0 500 0 500 5000 0 0\n" for i in range(4)))
write(BASE, "good.plsb", archive(a_object([("x", prop("double", a_double(1.5))),
                                           ("name", prop("string", a_str("robot")))])))
write(BASE, "good_archive.yaml", "plugslam_archive: 1\ndata:\n  x: {type: double, value: 1.5}\n"
      "  name: {type: string, value: robot}\n")

# -- YAML configs --
LOC = r"yaml:\d+"
case("yaml_syntax_unclosed", "plugins: [sim, odometry\nsource: {type: sim.Simulator2D\n", VALIDATE, 2,
     r"yaml_syntax_unclosed\.yaml:\d+:\d+: invalid YAML", "unclosed flow sequence", ext=".yaml")
case("yaml_truncated", GOOD_CONFIG[:GOOD_CONFIG.index("PriorSlice") + 3], VALIDATE, 2,
     r"yaml_truncated\.yaml:\d+:\d+: invalid YAML", "file cut inside a flow map", ext=".yaml")
case("yaml_empty", "", VALIDATE, 2, r"empty|expected a map", "empty file", ext=".yaml")
case("yaml_root_list", "- a\n- b\n", VALIDATE, 2, r"expected a map", "root is a list", ext=".yaml")
case("yaml_unknown_key", GOOD_CONFIG.replace("distance: 1.0", "distanse: 1.0"), VALIDATE, 2,
     r"distanse.*did you mean.*distance", "misspelt parameter", ext=".yaml")
case("yaml_wrong_type_number", GOOD_CONFIG.replace("distance: 1.0", "distance: far"), VALIDATE, 2,
     r"distance.*(number|double)", "string where a number is expected", ext=".yaml")
case("yaml_nan_param", GOOD_CONFIG.replace("distance: 1.0", "distance: .nan"), VALIDATE, 2,
     r"distance.*(finite|range|nan)", "NaN parameter", ext=".yaml")
case("yaml_inf_param", GOOD_CONFIG.replace("distance: 1.0", "distance: .inf"), VALIDATE, 2,
     r"distance.*(finite|range|inf)", "infinite parameter", ext=".yaml")
case("yaml_negative_param", GOOD_CONFIG.replace("distance: 1.0", "distance: -3"), VALIDATE, 2,
     r"distance.*(range|>|positive)", "out of range", ext=".yaml")
case("yaml_huge_int", GOOD_CONFIG.replace("min_inliers: 1", "min_inliers: 99999999999999999999999"),
     VALIDATE, 2, r"min_inliers", "integer overflow", ext=".yaml")
case("yaml_list_for_scalar", GOOD_CONFIG.replace("distance: 1.0", "distance: [1, 2]"), VALIDATE, 2,
     r"distance", "list where a scalar is expected", ext=".yaml")
case("yaml_unknown_type", GOOD_CONFIG.replace("sdk.DistanceSplitter", "sdk.NoSuchSplitter"),
     VALIDATE, 2, r"NoSuchSplitter", "unknown module type", ext=".yaml")
case("yaml_unknown_plugin", GOOD_CONFIG.replace("[sim, odometry]", "[sim, odometry, nosuchplugin]"),
     VALIDATE, 2, r"nosuchplugin", "plugin not found", ext=".yaml")
case("yaml_plugin_name_too_long", GOOD_CONFIG.replace("odometry.WheelOdometry", "e" * 300 + ".WheelOdometry"),
     VALIDATE, 2, r"plugin 'e+' not found", "type of a plugin whose file name is too long for the "
     "file system (found by fuzz_config: was an uncaught filesystem_error)", ext=".yaml")
case("yaml_plugins_wrong_type", GOOD_CONFIG.replace("[sim, odometry]", "{a: 1}"), VALIDATE, 2,
     r"plugins", "plugins is a map", ext=".yaml")
case("yaml_slot_wrong_type", GOOD_CONFIG.replace("motion: {type: odometry.WheelOdometry}",
                                                  "motion: 42"), VALIDATE, 2, r"motion",
     "a number where a module is expected", ext=".yaml")
case("yaml_binary_garbage", garbage(600, 7), VALIDATE, 2, r"yaml_binary_garbage\.yaml:\d+:\d+: (expected|invalid)",
     "random bytes", ext=".yaml")
case("yaml_deep_nesting", "a: " + "[" * 5000 + "]" * 5000 + "\n", VALIDATE, 2, r"yaml_deep_nesting\.yaml:\d+:\d+: invalid YAML",
     "5000 nested lists (stack exhaustion in a recursive parser)", ext=".yaml")
case("yaml_alias_bomb", "a: &a [x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a]\n"
     "c: &c [*b, *b, *b, *b, *b, *b, *b, *b]\nd: &d [*c, *c, *c, *c, *c, *c, *c, *c]\n"
     "e: [*d, *d, *d, *d, *d, *d, *d, *d]\n", VALIDATE, 2, r"unknown|expected|did you mean|'a'",
     "aliases expanding to 8^5 nodes at unknown root keys", ext=".yaml")
case("yaml_alias_cycle", "plugins: &p [io, *p]\n", VALIDATE, 2,
     r"yaml_alias_cycle\.yaml:1:\d+: invalid YAML: alias \*p is inside its own anchor &p",
     "an alias inside its own anchor (found by fuzz_config: a stack overflow, exit 139)", ext=".yaml")
case("yaml_alias_cycle_run", "plugins: &p [io, *p]\n", "run {file} -o {tmp}/out", 2,
     r"yaml_alias_cycle_run\.yaml:1:\d+: invalid YAML: alias \*p is inside its own anchor &p",
     "the same cycle given to run", ext=".yaml")
case("yaml_alias_deep", "a: &a [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[x]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]\n"
     + "".join(f"{chr(98 + i)}: &{chr(98 + i)} [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[*{chr(97 + i)}]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]\n"
               for i in range(9)), VALIDATE, 2, r"yaml_alias_deep\.yaml:\d+:\d+: invalid YAML: alias \*\w nests the document deeper than 256",
     "aliases of aliases nesting 320 deep, each line 32 deep", ext=".yaml")
case("yaml_alias_billion", "".join(f"{chr(97 + i)}: &{chr(97 + i)} [" + ", ".join([f"*{chr(96 + i)}" if i else "x"] * 10) + "]\n"
                                   for i in range(9)), VALIDATE, 2,
     r"yaml_alias_billion\.yaml:\d+:\d+: invalid YAML: aliases expand the document by more than 1000000 nodes",
     "aliases expanding to 10^9 nodes (the walks over the tree would run for hours)", ext=".yaml")
case("yaml_base_missing", "base: nowhere_to_be_found.yaml\nmax_frames: 3\n", VALIDATE, 2,
     r"yaml_base_missing\.yaml:1:7: base: the base config '.*nowhere_to_be_found\.yaml' is not a readable file",
     "a config starting from a file that does not exist", ext=".yaml")
case("yaml_base_self", "max_frames: 3\nbase: yaml_base_self.yaml\n", VALIDATE, 2,
     r"yaml_base_self\.yaml:2:7: base: a cycle of bases: .*yaml_base_self\.yaml -> .*yaml_base_self\.yaml",
     "a config starting from itself", ext=".yaml")
case("yaml_base_device", "base: /dev/zero\n", VALIDATE, 2,
     r"yaml_base_device\.yaml:1:7: base: the base config '/dev/zero' is not a readable file",
     "a base that is a device (endless): refused before reading", ext=".yaml")
case("yaml_missing_file", None, VALIDATE, 2, r"(cannot|could not) (open|read)|not found|does not exist",
     "config file missing", ext=".yaml")
case("yaml_bad_set_path", GOOD_CONFIG, "validate {file} --set pipeline..splitter.distance=1", 2,
     r"pipeline\.\.splitter", "malformed --set path", ext=".yaml")
case("yaml_set_index_out_of_range", GOOD_CONFIG,
     "validate {file} --set pipeline.tracker.aligner.slices[7].sigma=1", 2,
     r"slices\[7\]|index|out of range", "--set into a list element that does not exist", ext=".yaml")
case("yaml_duplicate_instance", GOOD_CONFIG.replace("{type: odometry.PriorSlice}",
     "{type: odometry.PriorSlice, name: p}\n        - {type: odometry.PriorSlice, name: p}"),
     VALIDATE, 2, r"\bp\b", "two modules with one instance name", ext=".yaml")

# -- CARMEN logs --
case("carmen_truncated_line", carmen_log(3) + "FLASER 30 2.0 2.0 2.0\n", CARMEN, 2,
     r"carmen_truncated_line\.log:\d+", "laser line cut short", ext=".log")
case("carmen_nan_ranges", carmen_log(12, ["nan", "inf", "-inf"] + [2.0] * 27), CARMEN, 0,
     r"12 frames in", "NaN/inf readings are no-returns, the run continues",
     ext=".log")
case("carmen_empty_scans", carmen_log(6) + "".join(flaser([], 101.0 + 0.1 * i) for i in range(3)),
     CARMEN, 0, r"\[warning\].*skipped 0 malformed line\(s\) and 3 empty scan\(s\)",
     "0-beam scans are skipped with a warning", ext=".log")
case("carmen_only_empty_scans", "".join(odom(100 + 0.1 * i) + flaser([], 100 + 0.1 * i)
                                        for i in range(3)), CARMEN, 2, r"no front-laser line.*3 empty scans \(skipped\)",
     "every scan is empty: nothing to run", ext=".log")
case("carmen_time_backwards", carmen_log(4) + odom(50.0) + flaser([2.0] * 30, 50.0), CARMEN, 0,
     r"\d+ timestamp\(s\) went backwards", "a clock jump backwards is flagged and the run continues", ext=".log")
case("carmen_binary_garbage", garbage(3000, 11), CARMEN, 2, r"carmen_binary_garbage\.log:1: unrecognised line",
     "random bytes", ext=".log")
case("carmen_huge_count", "FLASER 99999999999999 1 2 3\n", CARMEN, 2,
     r"carmen_huge_count\.log:1", "beam count larger than the line", ext=".log")
case("carmen_negative_count", "FLASER -5 1 2 3 0 0 0 0 0 0 1 h 1\n", CARMEN, 2,
     r"carmen_negative_count\.log:1", "negative beam count", ext=".log")
case("carmen_wrong_type", carmen_log(2) + "FLASER 3 a b c 0 0 0 0 0 0 101 h 101\n", CARMEN, 2,
     r"carmen_wrong_type\.log:5", "letters where ranges are expected", ext=".log")
case("carmen_skip_policy", carmen_log(6) + "FLASER 3 a b c 0 0 0 0 0 0 101 h 101\n" + carmen_log(2)
     .replace("100.", "102."), CARMEN + " --set source.on_error=skip", 0,
     r"\[warning\] .*carmen_skip_policy\.log:13: .*not a number.*line skipped[\s\S]*skipped 1 malformed line",
     "malformed line with on_error=skip: warned and skipped", ext=".log")
case("carmen_missing_file", None, CARMEN, 2, r"cannot open CARMEN log .*carmen_missing_file\.log", "log missing", ext=".log")
case("carmen_empty_file", "", CARMEN, 2, r"carmen_empty_file\.log' has no front-laser line", "empty log", ext=".log")
case("carmen_odom_only", "".join(odom(100 + 0.1 * i) for i in range(5)), CARMEN, 2,
     r"(?i)laser|scan", "no laser line", ext=".log")
case("carmen_inf_pose", carmen_log(2) + "ODOM inf 0 0 0 0 0 101 h 101\n" + flaser([2.0] * 30, 101.05),
     CARMEN, 2, r"carmen_inf_pose\.log:5", "infinite odometry pose", ext=".log")
case("carmen_robotlaser_truncated", "ROBOTLASER1 0 -1.5 3.14 0.01 80 0.01 0 5 1 1 1\n", CARMEN, 2,
     r"carmen_robotlaser_truncated\.log:1", "ROBOTLASER1 cut after the ranges", ext=".log")
gz = gzip.compress(carmen_log(12).encode(), mtime=0)
case("carmen_truncated_gzip", gz[: len(gz) // 2], CARMEN, 2, r"(?i)truncated|gzip",
     "gzip stream cut in half", ext=".log.gz")
case("carmen_gzip_garbage", b"\x1f\x8b\x08\x00" + garbage(400, 3), CARMEN, 2, r"(?i)gzip|corrupt",
     "gzip magic followed by garbage", ext=".log.gz")

# -- ROS bags --
case("bag_not_a_bag", "hello, I am a text file\n", ROSBAG, 2, r"(?i)bag_not_a_bag.*(magic|ROSBAG)",
     "wrong magic", ext=".bag")
case("bag_truncated_magic", MAGIC[:7], ROSBAG, 2, r"(?i)bag_truncated_magic", "file shorter than the magic",
     ext=".bag")
case("bag_magic_only", MAGIC + bag_header(), ROSBAG, 2, r"(?i)no message|empty|scan",
     "a valid bag without messages", ext=".bag")
good_bag = bag(chunk(scan_inner()))
case("bag_truncated", good_bag[: len(good_bag) * 2 // 3], ROSBAG, 2, r"(?i)truncated|end of file|short",
     "bag cut inside a chunk", ext=".bag")
case("bag_huge_header_length", MAGIC + bag_header() + u32(0xFFFFFFF0) + b"op=\x05", ROSBAG, 2,
     r"(?i)header|length|size", "record header length near 4 GiB", ext=".bag")
case("bag_unknown_compression", bag(chunk(scan_inner(), "zstd")), ROSBAG, 2, r"zstd",
     "unsupported chunk compression", ext=".bag")
case("bag_bz2_garbage", bag(chunk(scan_inner(), "bz2", payload=garbage(300, 5))), ROSBAG, 2,
     r"(?i)bz2", "bz2 chunk with garbage payload", ext=".bag")
case("bag_lz4_garbage", bag(chunk(scan_inner(), "lz4", payload=garbage(300, 6))), ROSBAG, 2,
     r"(?i)lz4", "lz4 chunk with garbage payload", ext=".bag")
case("bag_chunk_size_mismatch", bag(chunk(scan_inner(), size=12345)), ROSBAG, 2, r"(?i)size",
     "chunk size field disagrees with its data", ext=".bag")
case("bag_unknown_connection", bag(chunk(connection(0, "/scan", "sensor_msgs/LaserScan") +
                                         message(9, 10, 0, laser_scan(0, 10, [1.0] * 5)))),
     ROSBAG, 2, r"(?i)connection", "message on a connection never defined", ext=".bag")
case("bag_nan_ranges", bag(chunk(scan_inner(ranges=[float("nan"), float("inf")] + [1.5] * 18))),
     ROSBAG, 0, r"5 frames in", "NaN/inf ranges are no-returns", ext=".bag")
bad_scan = (connection(0, "/scan", "sensor_msgs/LaserScan") +
            message(0, 10, 0, laser_scan(0, 10, [1.0] * 5, count=1000000)))
case("bag_scan_count_too_large", bag(chunk(bad_scan)), ROSBAG, 2, r"(?i)LaserScan|ranges|bytes",
     "LaserScan claims a million ranges in 20 bytes", ext=".bag")
case("bag_time_backwards", bag(chunk(scan_inner(t0=20)), chunk(scan_inner(t0=10))), ROSBAG, 0,
     r"\[warning\].*10 message\(s\) older than one already read", "second chunk older than the first", ext=".bag")
case("bag_wrong_message_type", bag(chunk(scan_inner(scan_type="std_msgs/String"))), ROSBAG, 2,
     r"std_msgs/String", "the scan topic holds another type", ext=".bag")
case("bag_missing_file", None, ROSBAG, 2, r"cannot open ROS bag .*bag_missing_file\.bag", "bag missing", ext=".bag")
case("bag_binary_garbage", MAGIC + garbage(2000, 9), ROSBAG, 2, r"bag_binary_garbage\.bag: byte offset \d+: record",
     "magic then random bytes", ext=".bag")

# -- PGM worlds (sim.Simulator2D) --
px = bytes(255 if (x in (0, 19) or y in (0, 19)) else 0 for y in range(20) for x in range(20))
write(BASE, "world.pgm", pgm_p5(20, 20, px))
case("pgm_truncated", pgm_p5(20, 20, px)[:120], WORLD, 2, r"pgm_truncated\.pgm",
     "P5 pixels cut short", ext=".pgm")
case("pgm_garbage", garbage(800, 13), WORLD, 2, r"pgm_garbage\.pgm:1: expected magic number P2 or P5", "random bytes", ext=".pgm")
case("pgm_bad_magic", b"P7\n20 20\n255\n" + px, WORLD, 2, r"P2 or P5", "PAM magic", ext=".pgm")
case("pgm_huge_size", b"P5\n4000000000 4000000000\n255\n" + px, WORLD, 2,
     r"pgm_huge_size\.pgm", "4e9 x 4e9 pixels announced", ext=".pgm")
case("pgm_zero_maxval", b"P5\n20 20\n0\n" + px, WORLD, 2, r"(?i)maxval|max", "maxval 0", ext=".pgm")
case("pgm_negative_width", b"P2\n-3 2\n255\n0 0 0 0 0 0\n", WORLD, 2, r"pgm_negative_width\.pgm",
     "negative width", ext=".pgm")
case("pgm_p2_not_number", b"P2\n2 2\n255\n0 x 0 0\n", WORLD, 2, r"pgm_p2_not_number\.pgm",
     "letter among P2 pixels", ext=".pgm")
case("pgm_no_walls", pgm_p5(20, 20, b"\x00" * 400 if False else b"\xff" * 400), WORLD, 2,
     r"(?i)no occupied", "all free space: no wall to simulate", ext=".pgm")
case("pgm_missing", None, WORLD, 2, r"cannot open .*pgm_missing\.pgm", "world file missing", ext=".pgm")

# -- trajectories --
TUM_OK = "".join(f"{i:.1f} {0.1*i:.1f} 0 0 0 0 0 1\n" for i in range(10))
case("tum_truncated_line", TUM_OK + "10.0 1.0 0 0 0 0\n", ATE_TUM, 2,
     r"tum_truncated_line\.tum:11.*expected 8 columns", "7 columns", ext=".tum")
case("tum_nan", TUM_OK.replace("0.5 0 0", "nan 0 0"), ATE_TUM, 2, r"tum_nan\.tum:6",
     "NaN position", ext=".tum")
case("tum_inf_time", TUM_OK + "inf 1 0 0 0 0 0 1\n", ATE_TUM, 2, r"tum_inf_time\.tum:11",
     "infinite timestamp", ext=".tum")
case("tum_time_backwards", TUM_OK + "3.5 1 0 0 0 0 0 1\n", ATE_TUM, 2, r"backwards",
     "timestamp going backwards", ext=".tum")
case("tum_duplicate_time", TUM_OK + "9.0 1 0 0 0 0 0 1\n", ATE_TUM, 2, r"duplicate timestamp",
     "repeated timestamp", ext=".tum")
case("tum_wrong_type", TUM_OK.replace("0.3 0 0", "abc 0 0"), ATE_TUM, 2, r"tum_wrong_type\.tum:4",
     "letters where a number is expected", ext=".tum")
case("tum_zero_quaternion", TUM_OK + "10.0 1 0 0 0 0 0 0\n", ATE_TUM, 2, r"quaternion.*norm",
     "all-zero quaternion", ext=".tum")
case("tum_empty", "# only a comment\n", ATE_TUM, 2, r"(?i)no pose|empty", "no pose", ext=".tum")
case("tum_binary_garbage", garbage(1500, 17), ATE_TUM, 2, r"tum_binary_garbage\.tum:1: expected 8 columns",
     "random bytes", ext=".tum")
case("tum_missing", None, ATE_TUM, 2, r"cannot open .*tum_missing\.tum", "file missing", ext=".tum")
KITTI_OK = "".join(f"1 0 0 {0.1*i:.1f} 0 1 0 0 0 0 1 0\n" for i in range(10))
case("kitti_11_numbers", KITTI_OK + "1 0 0 1 0 1 0 0 0 0 1\n", ATE_KITTI, 2,
     r"kitti_11_numbers\.kitti:11", "11 numbers", ext=".kitti")
case("kitti_inf", KITTI_OK.replace("1 0 0 0.5", "1 0 0 inf"), ATE_KITTI, 2, r"kitti_inf\.kitti:6",
     "infinite translation", ext=".kitti")
case("kitti_not_rotation", KITTI_OK + "2 0 0 1 0 2 0 0 0 0 2 0\n", ATE_KITTI, 2,
     r"kitti_not_rotation\.kitti:11.*rotation", "scaled rotation block", ext=".kitti")
case("g2o_traj_huge_id", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1" + "5" * 130 + " 0 0 0\n", ATE_TUM, 2,
     r"g2o_traj_huge_id\.g2o:2: column 2 \(vertex id\): expected a non-negative integer up to 2\^53",
     "vertex id of 1.6e130 (found by fuzz_trajectory: was an overflowing cast, UB)", ext=".g2o")
case("g2o_traj_duplicate_vertex", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 1 2 0 0\n",
     ATE_TUM, 2, r"(?i)duplicate|twice", "vertex id repeated in a g2o trajectory", ext=".g2o")

# -- pose graphs (bad_input_tool graph = readGraphFile) --
G2O_OK = ("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
          "EDGE_SE2 0 1 1 0 0 500 0 0 500 0 5000\nEDGE_SE2 1 2 1 0 0 500 0 0 500 0 5000\n")
case("g2o_duplicate_vertex", G2O_OK + "VERTEX_SE2 1 5 5 0\n", GRAPH, 2,
     r"g2o_duplicate_vertex\.g2o:6.*1", "vertex id 1 twice", "tool", ext=".g2o")
case("g2o_edge_missing_vertex", G2O_OK + "EDGE_SE2 2 7 1 0 0 500 0 0 500 0 5000\n", GRAPH, 2,
     r"g2o_edge_missing_vertex\.g2o:6.*7", "edge to vertex 7 that does not exist", "tool", ext=".g2o")
case("g2o_non_pd_information", G2O_OK + "EDGE_SE2 0 2 2 0 0 -500 0 0 500 0 5000\n", GRAPH, 2,
     r"(?i)positive definite", "negative information diagonal: refused unless projected", "tool",
     ext=".g2o")
case("g2o_non_pd_optimize", G2O_OK + "EDGE_SE2 0 2 2 0 0 -500 0 0 500 0 5000\n",
     GRAPH + " --project-information", 0, r"projected 1", "--project-information: projected to the nearest PD matrix, optimised",
     "tool", ext=".g2o")
case("g2o_truncated_edge", G2O_OK + "EDGE_SE2 0 2 2 0 0 500 0\n", GRAPH, 2,
     r"g2o_truncated_edge\.g2o:6", "edge cut short", "tool", ext=".g2o")
case("g2o_nan_measurement", G2O_OK + "EDGE_SE2 0 2 nan 0 0 500 0 0 500 0 5000\n", GRAPH, 2,
     r"g2o_nan_measurement\.g2o:6", "NaN measurement", "tool", ext=".g2o")
case("g2o_inf_information", G2O_OK + "EDGE_SE2 0 2 2 0 0 inf 0 0 500 0 5000\n", GRAPH, 2,
     r"g2o_inf_information\.g2o:6", "infinite information entry", "tool", ext=".g2o")
case("g2o_not_a_tag", G2O_OK + "hello world\n", GRAPH, 2, r"g2o_not_a_tag\.g2o:6.*unknown record",
     "a line that is not a record", "tool", ext=".g2o")
case("g2o_wrong_type", G2O_OK.replace("VERTEX_SE2 2 2 0 0", "VERTEX_SE2 2 two 0 0"), GRAPH, 2,
     r"g2o_wrong_type\.g2o:3", "word where a number is expected", "tool", ext=".g2o")
case("g2o_binary_garbage", garbage(2000, 19), GRAPH, 2, r"g2o_binary_garbage\.g2o:1: binary data",
     "random bytes", "tool", ext=".g2o")
case("g2o_empty", "", GRAPH, 2, r"(?i)no (vertex|vertices|edge)|empty", "empty file", "tool", ext=".g2o")
case("g2o_mixed_dimensions", G2O_OK + "VERTEX_SE3:QUAT 3 0 0 0 0 0 0 1\n", GRAPH, 2,
     r"g2o_mixed_dimensions\.g2o:6", "2D and 3D records in one file", "tool", ext=".g2o")
case("g2o_huge_id", "VERTEX_SE2 99999999999999999999999 0 0 0\n", GRAPH, 2,
     r"g2o_huge_id\.g2o:1", "vertex id beyond 64 bits", "tool", ext=".g2o")
case("g2o_negative_id", "VERTEX_SE2 -4 0 0 0\nVERTEX_SE2 3 1 0 0\nEDGE_SE2 -4 3 1 0 0 1 0 0 1 0 1\n",
     GRAPH, 0, r"2 vertices, 1 edges", "negative vertex ids are legal g2o ids: accepted", "tool", ext=".g2o")
case("g2o_fix_missing_vertex", G2O_OK + "FIX 42\n", GRAPH, 2, r"g2o_fix_missing_vertex\.g2o:6",
     "FIX of a vertex that does not exist", "tool", ext=".g2o")
case("g2o_unknown_tag", G2O_OK + "VERTEX_FOO 3 0 0 0\n", GRAPH, 0, r"warning: skipped 1 record",
     "record of an unknown type: skipped with a warning, as g2o does", "tool", ext=".g2o")
case("g2o_self_edge", G2O_OK + "EDGE_SE2 1 1 0 0 0 500 0 0 500 0 5000\n", GRAPH, 2,
     r"g2o_self_edge\.g2o:6", "edge from a vertex to itself", "tool", ext=".g2o")
case("g2o_se3_bad_quaternion", "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 0\n", GRAPH, 2,
     r"g2o_se3_bad_quaternion\.g2o:1.*quaternion", "zero quaternion", "tool", ext=".g2o")
case("g2o_missing_file", None, GRAPH, 2, r"cannot open graph file .*g2o_missing_file\.g2o", "file missing", "tool", ext=".g2o")
TORO_OK = "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nEDGE2 0 1 1 0 0 500 0 500 5000 0 0\n"
case("toro_truncated", TORO_OK + "EDGE2 0 1 1 0\n", GRAPH, 2, r"toro_truncated\.toro:4",
     "TORO edge cut short", "tool", ext=".toro")
case("toro_non_pd", TORO_OK + "EDGE2 0 1 1 0 0 -1 0 1 1 0 0\n", GRAPH, 2,
     r"(?i)not positive definite", "TORO edge with a negative information entry", "tool", ext=".toro")
case("toro_missing_vertex", TORO_OK + "EDGE2 0 9 1 0 0 500 0 500 5000 0 0\n", GRAPH, 2,
     r"toro_missing_vertex\.toro:4.*9", "edge to vertex 9", "tool", ext=".toro")
case("toro_duplicate_vertex", TORO_OK + "VERTEX2 0 3 3 0\n", GRAPH, 2, r"toro_duplicate_vertex\.toro:4",
     "vertex 0 twice", "tool", ext=".toro")

# -- archives (bad_input_tool archive = loadArchiveFile + load(PropertyContainer)) --
good_payload = a_object([("x", prop("double", a_double(1.5)))])
good_arc = archive(good_payload)
case("archive_truncated", good_arc[:-5], ARCHIVE, 2, r"(?i)truncated|length|short",
     "binary archive cut short", "tool", ext=".plsb")
case("archive_bad_crc", archive(good_payload, crc=0xDEADBEEF), ARCHIVE, 2, r"(?i)crc|checksum",
     "checksum mismatch", "tool", ext=".plsb")
case("archive_bad_version", archive(good_payload, version=99), ARCHIVE, 2, r"version 99",
     "format version from the future", "tool", ext=".plsb")
case("archive_huge_length", archive(good_payload, length=1 << 62), ARCHIVE, 2, r"(?i)length|size",
     "payload length of 2^62 bytes", "tool", ext=".plsb")
case("archive_huge_count", archive(bytes([9]) + u32(0xFFFFFFFF)), ARCHIVE, 2, r"(?i)count|field|truncated",
     "object claims 4 billion fields (valid CRC)", "tool", ext=".plsb")
case("archive_wrong_type", archive(a_object([("x", prop("double", a_str("one")))])), ARCHIVE, 2,
     r"(?i)double|expected", "string where a double is expected (valid CRC)", "tool", ext=".plsb")
case("archive_unknown_tag", archive(a_object([("x", prop("quaternion9d", a_double(1)))])), ARCHIVE, 2,
     r"quaternion9d", "value type nobody registered", "tool", ext=".plsb")
case("archive_garbage", b"PLSB" + garbage(500, 23), ARCHIVE, 2, r"archive_garbage\.plsb: binary archive: ",
     "magic then random bytes", "tool", ext=".plsb")
case("archive_text_wrong_type", "plugslam_archive: 1\ndata:\n  x: {type: double, value: [1, 2]}\n",
     ARCHIVE, 2, r"archive_text_wrong_type\.yaml:\d+: text archive.*x\.value.*double", "YAML archive with a list for a double", "tool", ext=".yaml")
case("archive_text_not_archive", "x: {type: double, value: 1.5}\n", ARCHIVE, 2,
     r"missing 'plugslam_archive'", "a YAML file that is not a plugslam archive", "tool", ext=".yaml")
case("archive_text_future_version", "plugslam_archive: 7\ndata: {}\n", ARCHIVE, 2, r"version",
     "text archive from a newer format version", "tool", ext=".yaml")
case("archive_text_garbage", garbage(700, 29), ARCHIVE, 2,
     r"archive_text_garbage\.yaml:\d+: text archive: invalid YAML",
     "random bytes (not PLSB: read as YAML)", "tool", ext=".yaml")
case("archive_empty", "", ARCHIVE, 2, r"archive_empty\.plsb: text archive: expected a map", "empty file", "tool", ext=".plsb")
case("archive_missing", None, ARCHIVE, 2, r"cannot open .*archive_missing\.plsb", "file missing", "tool", ext=".plsb")


# -- camera datasets (issue 15): each case is a small dataset folder --
def without(files, *names):
    return {k: v for k, v in files.items() if k not in names}


good_kitti = kitti_folder()
case("cam_kitti_ok", good_kitti, KITTI, 0, r"2 frames", "a valid two-pair KITTI folder reads")
case("cam_kitti_corrupt_png", dict(good_kitti, **{"image_0/000001.png": grey_png()[:60]}), KITTI, 2,
     r"frame 1 of 2: .*image_0/000001\.png: corrupt PNG", "left image cut inside IDAT")
case("cam_kitti_garbage_png", dict(good_kitti, **{"image_1/000000.png": garbage(300, 41)}), KITTI, 2,
     r"frame 0 of 2: .*image_1/000000\.png: not a PNG or JPEG", "random bytes named .png")
case("cam_kitti_missing_image", without(good_kitti, "image_1/000001.png"), KITTI, 2,
     r"frame 1 of 2: cannot open '.*image_1/000001\.png'", "right image missing")
case("cam_kitti_missing_image_skip", without(good_kitti, "image_1/000001.png"),
     KITTI + " --set source.on_error=skip", 0, r"\[warning\].*image_1/000001\.png.*frame skipped",
     "right image missing, on_error: skip warns and goes on")
case("cam_kitti_calib_without_p1", dict(good_kitti, **{"calib.txt": KITTI_CALIB.split("\n")[0] + "\n"}),
     KITTI, 2, r"calib\.txt: missing key 'P1' \(keys present: P0\)", "calibration lacks the right camera")
case("cam_kitti_calib_short_p0", dict(good_kitti, **{"calib.txt": "P0: 700 0 4\n" + KITTI_CALIB.split("\n")[1] + "\n"}),
     KITTI, 2, r"calib\.txt:1: P0: expected 12 numbers, got 3", "projection matrix cut short")
case("cam_kitti_times_short", dict(good_kitti, **{"times.txt": "0.0\n"}), KITTI, 2,
     r"times\.txt: has 1 times, but the images go up to 000001\.png", "times.txt shorter than the images")
case("cam_kitti_size_mismatch", dict(good_kitti, **{"image_1/000000.png": grey_png(6, 8)}), KITTI, 2,
     r"image_1/000000\.png: image is 6x8, the calibration's is 8x8", "right image of another size")
case("cam_kitti_no_images", {"calib.txt": KITTI_CALIB, "times.txt": "0.0\n", "image_0/readme.txt": "x"},
     KITTI, 2, r"holds no images named by a number", "no numbered images")
case("cam_kitti_missing_folder", None, KITTI, 2, r"dataset folder '.*cam_kitti_missing_folder' does not exist",
     "dataset folder missing")

raw = {"calib_cam_to_cam.txt": "calib_time: 09-Jan-2012 13:57:47\nS_rect_00: 8 8\n"
       "P_rect_00: 700 0 4 0 0 700 4 0 0 0 1 0\nP_rect_01: 700 0 4 -350 0 700 4 0 0 0 1 0\n",
       "image_00/timestamps.txt": "2011-09-26 13:02:25.967790592\n2011-09-26 13:02:26.070920448\n"}
for cam in ("image_00", "image_01"):
    for i in range(2):
        raw[f"{cam}/data/{i:010d}.png"] = grey_png(seed=i)
case("cam_kitti_raw_bad_timestamp", dict(raw, **{"image_00/timestamps.txt":
     "2011-09-26 13:02:25.967790592\n2011-09-26 13:02\n"}), KITTI_RAW, 2,
     r"timestamps\.txt:2: expected 'YYYY-MM-DD HH:MM:SS\.fffffffff'", "timestamp cut short")
case("cam_kitti_raw_without_s_rect", dict(raw, **{"calib_cam_to_cam.txt": raw["calib_cam_to_cam.txt"].replace("S_rect_00: 8 8\n", "")}),
     KITTI_RAW, 2, r"calib_cam_to_cam\.txt: missing key 'S_rect_00'", "calibration without the rectified size")

good_euroc = euroc_folder()
case("cam_euroc_ok", good_euroc, EUROC, 0, r"2 frames", "a valid two-pair EuRoC folder reads")
case("cam_euroc_sensor_without_intrinsics", dict(good_euroc, **{"mav0/cam1/sensor.yaml": euroc_sensor(0.09, "intrinsics")}),
     EUROC, 2, r"cam1/sensor\.yaml: missing key 'intrinsics'", "sensor.yaml lacks the intrinsics")
case("cam_euroc_sensor_without_tbs", dict(good_euroc, **{"mav0/cam0/sensor.yaml": euroc_sensor(0.0, "T_BS")}),
     EUROC, 2, r"cam0/sensor\.yaml: missing key 'T_BS'", "sensor.yaml lacks the extrinsics")
case("cam_euroc_resolution_beyond_int", dict(good_euroc, **{"mav0/cam0/sensor.yaml":
     euroc_sensor(0.0).replace("resolution: [8, 8]", "resolution: [8.8e57, 8]")}), EUROC, 2,
     r"cam0/sensor\.yaml:7: resolution: expected \[width, height\] in whole pixels from 1 to 65536, "
     r"got width 8\.8e\+57", "a resolution beyond int (the camera-files fuzzer's finding)")
case("cam_euroc_bad_csv", dict(good_euroc, **{"mav0/cam0/data.csv":
     good_euroc["mav0/cam0/data.csv"] + "14037152733x,a.png\n"}), EUROC, 2,
     r"cam0/data\.csv:4: timestamp \[ns\]: '14037152733x' is not an integer", "malformed data.csv row")
case("cam_euroc_no_camera", {"mav0/cam0/sensor.yaml": euroc_sensor(0.0)}, EUROC, 2,
     r"no camera folder '.*cam1'", "second camera folder missing")

good_tum = tum_folder()
case("cam_tum_ok", good_tum, TUM, 0, r"2 frames", "a valid two-frame TUM folder reads")
case("cam_tum_depth_wrong_size", dict(good_tum, **{"depth/1.033333.png": depth_png(6, 8)}), TUM, 2,
     r"frame 1 of 2: .*depth/1\.033333\.png: depth image is 6x8, expected 8x8", "depth image of the wrong size")
case("cam_tum_depth_8bit", dict(good_tum, **{"depth/1.033333.png": grey_png()}), TUM, 2,
     r"depth/1\.033333\.png: depth image is 8-bit grey, expected a 16-bit grey PNG", "8-bit depth image")
case("cam_tum_truncated_jpeg", dict(tum_folder(2, ".jpg"), **{"rgb/1.033333.jpg": grey_jpeg()[:-10]}), TUM, 2,
     r"frame 1 of 2: .*rgb/1\.033333\.jpg: corrupt JPEG", "colour JPEG cut short (7-Scenes' colour is JPEG)")
case("cam_tum_jpeg_ok", tum_folder(2, ".jpg"), TUM, 0, r"2 frames", "JPEG colour reads")
case("cam_tum_no_association", dict(good_tum, **{"depth.txt": "5.0 depth/1.000000.png\n"}), TUM, 2,
     r"no colour image has a depth image within 0\.02", "colour and depth times never meet")
case("cam_tum_list_garbage", dict(good_tum, **{"rgb.txt": garbage(200, 43)}), TUM, 2,
     r"rgb\.txt:\d+", "random bytes as rgb.txt")
case("cam_tum_bad_intrinsics_file", dict(good_tum, **{"camera-intrinsics.txt": "585 0 320\n0 585 240\n"}),
     TUM + " --set source.intrinsics_file=camera-intrinsics.txt", 2,
     r"camera-intrinsics\.txt:2: expected a 3x3 camera matrix", "K file with two rows")

good_folder = rgbd_folder()
case("cam_rgbd_folder_pose_count", dict(good_folder, **{"pose.txt": "0 0 0 0 0 0 1\n"}), RGBD_FOLDER, 2,
     r"pose\.txt: has 1 poses for 2 colour images", "pose list shorter than the images")
case("cam_rgbd_folder_ok", good_folder, RGBD_FOLDER, 0, r"2 frames", "a valid slambook-style folder reads")


# ---- manifest --------------------------------------------------------------------------------


def yq(s):
    return "'" + str(s).replace("'", "''") + "'"


lines = ["# Bad-input corpus: one entry per case, generated by generate.py (edit the table there).",
         "# command: arguments of build/bin/plugslam (binary: tool = the test's bad_input_tool,",
         "# which reads pose graphs and archives like `plugslam optimize` and the session loader do);",
         "# placeholders {file} the case file, {dir} this folder, {tmp} a fresh temporary folder;",
         "# missing: true = the file must not exist (missing-file cases).",
         "# exit: expected exit code (2 = bad input, 0 = warned and continued); pattern: a regex",
         "# (ECMAScript) the combined stdout+stderr must contain.",
         "cases:"]
for c in cases:
    lines.append(f"  - name: {c['name']}")
    for k in ("file", "missing", "command", "exit", "pattern", "binary", "why"):
        if k in c:
            v = c[k]
            lines.append(f"    {k}: {v if k == 'exit' else 'true' if v is True else yq(v)}")
with open(os.path.join(HERE, "cases.yaml"), "w") as f:
    f.write("\n".join(lines) + "\n")
print(f"{len(cases)} cases")
