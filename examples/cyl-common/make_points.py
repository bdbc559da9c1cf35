#!/usr/bin/env python3
"""Writes the point sets shared by the cyl-* experiments (thesis §3.4), independent of any mesh so
that a fine ground-truth mesh and the coarse estimation mesh observe the same material points:
  markers.csv     15 observed markers on part of the front (+y) surface, 0.5 mm under it;
  validation.csv  425 validation points filling the cylinder (r 0..12 mm, z 1..17 cm).
Units: metres. Cylinder: radius 0.015 m, axis z from 0 to 0.18 m."""
import math

with open("markers.csv", "w") as f:
    f.write("x,y,z\n")
    for z in (0.03, 0.06, 0.09, 0.12, 0.15):
        for deg in (60.0, 90.0, 120.0):
            a = math.radians(deg)
            f.write(f"{0.0145 * math.cos(a):.6f},{0.0145 * math.sin(a):.6f},{z:.3f}\n")

with open("validation.csv", "w") as f:
    f.write("x,y,z\n")
    for k in range(17):
        z = 0.01 * (k + 1)
        f.write(f"0.000000,0.000000,{z:.3f}\n")
        for r in (0.004, 0.008, 0.012):
            for j in range(8):
                a = 2.0 * math.pi * j / 8.0
                f.write(f"{r * math.cos(a):.6f},{r * math.sin(a):.6f},{z:.3f}\n")
