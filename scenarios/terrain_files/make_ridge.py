#!/usr/bin/env python3
"""Writes ridge.obj: 24 x 24 m of rolling ground crossed by a 1.2 m ridge along x = 0 with steep
sides (39 deg) and one low pass at |y| < 2 m. A triangle grid every 0.5 m, z up, metres in W."""
import math

STEP = 0.5
HALF = 12.0


def height(x, y):
    ground = 0.3 * math.sin(0.25 * x) * math.cos(0.2 * y)
    # the ridge's crest height along y: 0.1 m in the pass, 1.2 m beyond |y| = 3.5 m
    t = min(1.0, max(0.0, (abs(y) - 2.0) / 1.5))
    crest = 0.1 + 1.1 * t * t * (3.0 - 2.0 * t)
    return ground + crest * max(0.0, 1.0 - abs(x) / 1.5)


def main():
    n = int(round(2 * HALF / STEP)) + 1
    with open("ridge.obj", "w") as out:
        out.write("# ridge.obj: written by make_ridge.py (trav, scenarios/terrain_files)\n")
        for j in range(n):
            for i in range(n):
                x, y = -HALF + i * STEP, -HALF + j * STEP
                out.write(f"v {x:.3f} {y:.3f} {height(x, y):.4f}\n")
        for j in range(n - 1):
            for i in range(n - 1):
                a = j * n + i + 1  # OBJ indices start at 1
                b, c, d = a + 1, a + n, a + n + 1
                out.write(f"f {a} {b} {d}\nf {a} {d} {c}\n")


if __name__ == "__main__":
    main()
