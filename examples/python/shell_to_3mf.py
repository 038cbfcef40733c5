#!/usr/bin/python3
"""Points (a file snvr reads, or a numpy array) to a printable shell, written as 3MF.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/shell_to_3mf.py [POINTS] [-o OUT] [--resolution N]

Without POINTS a numpy sphere with a few stray points is used.
"""
import argparse
import sys
import time

import numpy as np

import snvr


def demo_points():
    """A sphere of radius 1 sampled by a Fibonacci spiral, and three stray points."""
    n = 20000
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    r = np.sqrt(1 - z * z)
    phi = np.pi * (1 + 5 ** 0.5) * i
    sphere = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    return np.concatenate([sphere, [[3.0, 0, 0], [0, -2.5, 1], [1.5, 1.5, 1.5]]])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("points", nargs="?", help="a point file (.ply, .las, .xyz, ...); default: a numpy sphere")
    parser.add_argument("-o", "--output", default="shell.3mf", help="the mesh to write (.3mf, .stl, .ply, .obj)")
    parser.add_argument("--resolution", type=int, default=128, help="cells on the longest axis")
    args = parser.parse_args()

    start = time.perf_counter()
    points = snvr.read_points(args.points) if args.points else demo_points()

    def progress(stage, step, steps):
        if stage == "step":
            print(f"\rstep {step}/{steps}", end="", file=sys.stderr, flush=True)
        return True  # False would cancel the run (snvr.Cancelled)

    shell = snvr.shell(points, resolution=args.resolution, written_as=args.output, progress=progress)
    print(file=sys.stderr)
    shell.write(args.output)
    report = shell.report
    print(f"{len(points):,} points, {int(shell.outlier_mask.sum()):,} dropped as outliers")
    print(f"{len(shell.faces):,} triangles; closed {report['mesh']['closed']}, manifold {report['mesh']['manifold']}, "
          f"{report['mesh']['solid_pieces']} solid piece(s), genus {report['check']['genus']}")
    print(f"points inside: {report['check']['points_inside']:,}, the shallowest "
          f"{report['check']['depth_min_l']:.3f} x offset deep; offset {report['offset']['length']:.4g} mm")
    for warning in shell.warnings:
        print("warning:", warning)
    print(f"wrote {args.output} in {time.perf_counter() - start:.2f} s")


if __name__ == "__main__":
    main()
