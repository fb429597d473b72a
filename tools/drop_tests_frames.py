#!/usr/bin/python3
"""tools/drop_tests_frames.py - what the VTK frames of an axisymmetric run
(`rockfuzz impact ... --vtk DIR`) say about the soil under the block: the
diagnosis of JGGE24-L1 in docs/validation-plastic.md section 8.

Usage: /usr/bin/python3 tools/drop_tests_frames.py DIR [DEPTH_M] [FRAME]
  DIR      the --vtk directory (fem_NNNN.vtu)
  DEPTH_M  elements whose reference centroid is above -DEPTH_M count as the
           layer (default 1.0 m)
  FRAME    frame index (default: the last one)
Prints the block's sink and speed, the range of the volume ratio J of the
layer's elements (exact axisymmetric volume: two triangles, area x centroid
radius, against the reference one), the six elements with the smallest
stable size (area / longest diagonal) relative to their reference size, and
the most compacted and most dilated layer elements.  Units: m, s, MPa.
"""
import glob
import os
import re
import sys

import numpy as np


def load(path):
    """Points, displacement, velocity, connectivity, cell data of one frame."""
    text = open(path).read()
    out = {"t": float(re.search(r"t = ([^ ]+) s", text).group(1))}
    for head, body in re.findall(r"<DataArray([^>]*)>(.*?)</DataArray>", text, re.S):
        m = re.search(r'Name="([^"]*)"', head)
        a = np.array(body.split(), float)
        if 'NumberOfComponents="3"' in head:
            a = a.reshape(-1, 3)
        out[m.group(1) if m else "points"] = a
    out["connectivity"] = out["connectivity"].astype(int).reshape(-1, 4)
    out["body"] = out["body"].astype(int)
    return out


def tri(p, q, r):
    """Axisymmetric volume / 2 pi and area of triangles (arrays of points)."""
    a = 0.5 * ((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (r[:, 0] - p[:, 0]) * (q[:, 1] - p[:, 1]))
    return a * (p[:, 0] + q[:, 0] + r[:, 0]) / 3, a


def geometry(x, conn):
    c = x[conn]
    v1, a1 = tri(c[:, 0], c[:, 1], c[:, 2])
    v2, a2 = tri(c[:, 0], c[:, 2], c[:, 3])
    d = np.maximum(np.hypot(*(c[:, 2] - c[:, 0]).T), np.hypot(*(c[:, 3] - c[:, 1]).T))
    return v1 + v2, (a1 + a2) / d, c[:, :, 0].mean(1), c[:, :, 1].mean(1)


def main():
    files = sorted(glob.glob(os.path.join(sys.argv[1], "fem_*.vtu")))
    depth = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    first = load(files[0])
    frame = load(files[int(sys.argv[3])] if len(sys.argv) > 3 else files[-1])
    conn, body, x0 = first["connectivity"], first["body"], first["points"][:, :2]
    x = x0 + frame["displacement"][:, :2]
    v0, h0, r0, z0 = geometry(x0, conn)
    v, h, r, z = geometry(x, conn)
    J, hr = v / v0, h / h0
    layer = (body == 1) & (z0 > -depth)
    p = -(frame["sigma_rr"] + frame["sigma_zz"] + frame["sigma_tt"]) / 3e6
    eps = frame["equivalent_plastic_strain"]
    bn = np.unique(conn[body == 0])
    print("t %.4f s: block sunk %.3f m, moving at %.3f m/s" % (
        frame["t"], -frame["displacement"][bn, 1].mean(), frame["velocity"][bn, 1].mean()))
    print("layer: %d elements, J from %.3f to %.3f" % (layer.sum(), J[layer].min(), J[layer].max()))
    print("thinnest elements (stable size / reference):")
    for e in np.argsort(np.where(body == 1, hr, np.inf))[:6]:
        print("  %d  ref (r %.3f, z %.3f) now (r %.3f, z %.3f)  size %.3f  J %.3f  eps_p %.2f  p %.2f MPa" % (
            e, r0[e], z0[e], r[e], z[e], hr[e], J[e], eps[e], p[e]))
    for name, e in (("most compacted", np.argmin(np.where(layer, J, np.inf))),
                    ("most dilated", np.argmax(np.where(layer, J, -np.inf)))):
        print("%s: %d  ref (r %.3f, z %.3f)  J %.3f  eps_p %.2f  p %.2f MPa" % (
            name, e, r0[e], z0[e], J[e], eps[e], p[e]))


if __name__ == "__main__":
    main()
