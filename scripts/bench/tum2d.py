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


def take_options(args, opts):
    """Moves each `KEY VALUE` of opts' keys from args into opts, typed as its default."""
    for key in list(opts):
        if key in args:
            k = args.index(key)
            opts[key] = type(opts[key])(args[k + 1])
            del args[k:k + 2]
    return opts


def matched(trajs):
    """[(i, [trajs[0][i], each other trajectory's pose at its stamp])] for the poses of trajs[0]
    that every other trajectory has (stamps matched to the microsecond)."""
    by_time = [{round(p[0], 6): p for p in t} for t in trajs[1:]]
    rows = []
    for i, r in enumerate(trajs[0]):
        other = [m.get(round(r[0], 6)) for m in by_time]
        if all(other):
            rows.append((i, [r] + other))
    return rows
