#!/usr/bin/env python3
"""How well a diffuse cone set integrates irradiance, without voxels.

Each cone of a set is taken as the uniform average of the radiance over its
aperture (the ideal a voxel cone approaches; directions below the horizon
dropped), weighted pi / count as host/vct/ConeTracing.cpp weights it, and
compared with the exact cosine-weighted irradiance for radiance fields
around a surface at random orientations: a lit half-space (a wall's edge),
a cos^4 lobe, and lit caps of 30 and 60 degrees. Prints the relative RMS
error of each set (lower is better) for the former sunflower spiral and the
ring set diffuseCones() builds now. Monte Carlo with a fixed seed, so the
table is the same on every run; needs numpy.

  python3 scripts/cone_set_quadrature.py [--counts 5,9,16] [--aperture 45]
  python3 scripts/cone_set_quadrature.py --print-set 9   # the ring set's directions, one per line
"""
import argparse
import math
import sys

try:
    import numpy as np
except ImportError:
    sys.exit("cone_set_quadrature.py: needs numpy (Debian: apt-get install python3-numpy)")


def sunflower(n):
    """The former set: the disk's centre, then one cone per equal-area ring at the golden angle."""
    dirs = []
    for i in range(n):
        r = 0.0 if i == 0 else math.sqrt((i + 0.5) / n)
        phi = i * math.pi * (3.0 - math.sqrt(5.0))
        dirs.append((r * math.cos(phi), r * math.sin(phi), math.sqrt(max(0.0, 1.0 - r * r))))
    return np.array(dirs)


def cone_rings(n):
    """coneRings() of host/vct/ConeTracing.cpp."""
    if n <= 3:
        return [n]
    rings = max(1, int(math.floor(math.sqrt(n) / 2.0 + 0.5)))
    rest = n - 1
    return [1] + [rest // rings + (1 if j >= rings - rest % rings else 0) for j in range(rings)]


def rings(n):
    """diffuseCones() of host/vct/ConeTracing.cpp."""
    counts = cone_rings(n)
    r2, area, moment = [], 0.0, 0.0
    for j, k in enumerate(counts):
        band = k / n
        r2.append(0.0 if (k == 1 and j == 0) else area + 0.5 * band)
        moment += band * r2[-1]
        area += band
    dirs = []
    for j, k in enumerate(counts):
        r = math.sqrt(min(1.0, r2[j] * 0.5 / moment)) if moment > 0 else 0.0
        for i in range(k):
            phi = 2.0 * math.pi * (i + 0.5 * (j % 2)) / k
            dirs.append((r * math.cos(phi), r * math.sin(phi), math.sqrt(max(0.0, 1.0 - r * r))))
    return np.array(dirs)


def cone_samples(rng, axis, half_angle, count):
    """Directions uniform over the cone's solid angle."""
    cos_t = 1.0 - rng.random(count) * (1.0 - math.cos(half_angle))
    sin_t = np.sqrt(1.0 - cos_t**2)
    phi = 2.0 * math.pi * rng.random(count)
    t = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.5 else [0.0, 1.0, 0.0])
    t /= np.linalg.norm(t)
    b = np.cross(axis, t)
    return np.outer(sin_t * np.cos(phi), t) + np.outer(sin_t * np.sin(phi), b) + np.outer(cos_t, axis)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--counts", default="5,9,16")
    ap.add_argument("--aperture", type=float, default=45.0, help="full cone aperture, degrees")
    ap.add_argument("--fields", type=int, default=1000, help="random orientations per field")
    ap.add_argument("--print-set", type=int, metavar="N", help="print the N-cone ring set (x y z per line) and exit")
    a = ap.parse_args()
    if a.print_set is not None:
        if not 1 <= a.print_set <= 32:
            sys.exit("--print-set: expected 1..32, got %d" % a.print_set)
        for d in rings(a.print_set):
            print("%.6f %.6f %.6f" % tuple(d))
        return
    try:
        counts = [int(c) for c in a.counts.split(",")]
    except ValueError:
        sys.exit("--counts: expected comma-separated integers, got " + a.counts)
    if any(c < 1 or c > 32 for c in counts) or not 0 < a.aperture < 180 or a.fields < 1:
        sys.exit("--counts in 1..32, --aperture in (0, 180), --fields >= 1")
    rng = np.random.default_rng(2026)
    m = rng.normal(size=(a.fields, 3))
    m /= np.linalg.norm(m, axis=1)[:, None]
    u, v = rng.random(100000), rng.random(100000)
    hemisphere = np.stack([np.sqrt(u) * np.cos(2 * np.pi * v), np.sqrt(u) * np.sin(2 * np.pi * v), np.sqrt(1 - u)], 1)
    fields = {
        "half-space": lambda s: (s @ m.T > 0).astype(float),
        "cos^4 lobe": lambda s: np.maximum(s @ m.T, 0) ** 4,
        "30-degree cap": lambda s: (s @ m.T > math.cos(math.radians(30))).astype(float),
        "60-degree cap": lambda s: (s @ m.T > math.cos(math.radians(60))).astype(float),
    }
    half = math.radians(a.aperture) / 2
    print("relative RMS error of E / pi over %d orientations, %g-degree cones" % (a.fields, a.aperture))
    print("| cones | set | " + " | ".join(fields) + " | mean |")
    print("|---:|---|" + "---:|" * (len(fields) + 1))
    for n in counts:
        for name, dirs in (("sunflower", sunflower(n)), ("rings " + "+".join(map(str, cone_rings(n))), rings(n))):
            errs = []
            for f in fields.values():
                exact = f(hemisphere).mean(0)
                estimate = np.zeros(len(m))
                for d in dirs:
                    s = cone_samples(rng, d / np.linalg.norm(d), half, 600)
                    s = s[s[:, 2] > 0]
                    estimate += f(s).mean(0) / n
                errs.append(math.sqrt(((estimate - exact) ** 2).mean() / (exact**2).mean()))
            print("| %d | %s | %s | %.3f |" % (n, name, " | ".join("%.3f" % e for e in errs), sum(errs) / len(errs)))


if __name__ == "__main__":
    main()
