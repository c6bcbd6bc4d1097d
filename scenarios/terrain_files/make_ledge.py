#!/usr/bin/env python3
"""Writes ledge.raw: 30 x 24 m (x from -15 to 15, y from -12 to 12) of ground with a plateau 1 m
high at x >= 0. Along |y| <= 5 m its west edge is a cliff (1 m down within 0.2 m); beyond |y| = 5.4 m
it goes down a 9.5 deg slope (1 m over 6 m) instead, and between the two the cliff gives way to the
slope. Float32 heights [m], little-endian, 151 x 121 samples every 0.2 m, rows along +y from the
smallest y, x fastest (terrain type `heightmap`, docs/terrains.md)."""
import struct

STEP = 0.2
HALF_X, HALF_Y = 15.0, 12.0


def smoothstep(t):
    t = min(1.0, max(0.0, t))
    return t * t * (3.0 - 2.0 * t)


def height(x, y):
    if x >= 0.0:
        return 1.0
    cliff = 1.0 - smoothstep((abs(y) - 5.0) / 0.4)  # 1 along the cliff, 0 on the slopes
    slope = 1.0 - min(1.0, -x / 6.0)  # the slope's height below the plateau's edge
    return (1.0 - cliff) * slope


def main():
    nx = int(round(2 * HALF_X / STEP)) + 1
    ny = int(round(2 * HALF_Y / STEP)) + 1
    with open("ledge.raw", "wb") as out:
        for j in range(ny):
            for i in range(nx):
                out.write(struct.pack("<f", height(-HALF_X + i * STEP, -HALF_Y + j * STEP)))
    print(f"ledge.raw: {nx} x {ny} samples")


if __name__ == "__main__":
    main()
