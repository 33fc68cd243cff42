"""Planar poses from TUM trajectory files, shared by the bench's Python scripts."""
import math


def load(path):
    """[(stamp, x, y, yaw)] of a TUM file (`t x y z qx qy qz qw`), comments and blanks skipped."""
    poses = []
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            v = [float(x) for x in line.split()]
            qx, qy, qz, qw = v[4:8]
            poses.append((v[0], v[1], v[2], math.atan2(2 * (qw * qz + qx * qy),
                                                      1 - 2 * (qy * qy + qz * qz))))
    return poses


def relative(a, b):
    """(dx, dy, dyaw) of pose b in pose a's frame; poses as load() gives them."""
    c, s = math.cos(a[3]), math.sin(a[3])
    dx, dy = b[1] - a[1], b[2] - a[2]
    return (c * dx + s * dy, -s * dx + c * dy, math.remainder(b[3] - a[3], 2 * math.pi))
