#!/usr/bin/env python3
"""make_terrain_example.py - the synthetic rockfall terrain of examples/terrain/.

A slope 500 m long (west to east, x) and 300 m wide (y), in Swiss LV95
(EPSG:2056) coordinates, 2 m cells, that a rockfall engineer recognises:

  s < 0            the plateau above the cliff (8 deg)           rock
  s =   0 -  55 m  the cliff, 60 deg, 95 m high                  rock
  s =  55 - 180 m  the upper talus slope, 35 deg                  talus
  s = 180 - 235 m  a bench, a flatter step of 8 deg               talus
  s = 235 - 315 m  the lower talus slope, 28 deg                  talus
  s > 315 m        the runout zone, 10 deg easing to 4 deg,       soil (forest floor)
                   with a gully that starts on the bench and
                   deepens to 8 m, and a broad trough that
                   gathers blocks toward it

(s is the distance east of the cliff's top edge, at x = 60 to 75 m: it
bows out east in the middle of the slope.)
The slope angles blend over about 8 m, and a few metres of deterministic
undulation (sums of sines, no random numbers) make the surface less
ideal.  Written, in the folder given (default examples/terrain):

  dem.asc, dem.prj          the DEM: ESRI ASCII grid, 251 x 151 nodes (cell centres) 2 m apart
  classes.asc, classes.prj  material classes 1 rock, 2 talus, 3 soil on the 250 x 150 cells of the
                            bilinear surface (each class cell centred in a surface cell)
  release.geojson           the release polygon: a strip along the top edge of the cliff

Plain python3, no packages, deterministic: the same bytes every run.
Usage: python3 tools/make_terrain_example.py [FOLDER]
"""
import math
import os
import sys

X0, Y0 = 2612000.0, 1165000.0   # south-west node [m], LV95
CELL = 2.0                      # [m]
NX, NY = 251, 151               # nodes: 500 m x 300 m
TOP = 1480.0                    # height of the cliff's top edge [m]

# (start s [m], slope angle [deg]) of each stretch, west to east
STRETCHES = [(-90, 8), (0, 60), (55, 35), (180, 8), (235, 28), (315, 10), (375, 6), (415, 4)]
BLEND = 4.0                     # half width of the blend between two stretches [m]
RELEASE_BACK = 14.0             # the release strip: from this far behind the cliff edge ...
RELEASE_FRONT = 1.0             # ... to this far behind it [m]

WKT = ('PROJCS["CH1903+_LV95",GEOGCS["GCS_CH1903+",DATUM["D_CH1903+",SPHEROID["Bessel_1841",6377397.155,'
       '299.1528128]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]],PROJECTION['
       '"Hotine_Oblique_Mercator_Azimuth_Center"],PARAMETER["False_Easting",2600000.0],PARAMETER['
       '"False_Northing",1200000.0],PARAMETER["Scale_Factor",1.0],PARAMETER["Azimuth",90.0],PARAMETER['
       '"Longitude_Of_Center",7.439583333333333],PARAMETER["Latitude_Of_Center",46.95240555555556],'
       'UNIT["Meter",1.0]]')


def tangent(s):
    """Slope tan(angle) at distance s east of the cliff line, blended smoothly between stretches."""
    t = math.tan(math.radians(STRETCHES[0][1]))
    for start, deg in STRETCHES[1:]:
        w = 0.5 * (1 + math.tanh((s - start) / BLEND))
        t += w * (math.tan(math.radians(deg)) - t)
    return t


def drop_table():
    """Drop below the top at s = -90 .. 500 m every 0.25 m (trapezoidal integral of the slope)."""
    step, s, d, table = 0.25, -90.0, 0.0, []
    while s <= 500.0 + step:
        table.append(d)
        d += 0.5 * step * (tangent(s) + tangent(s + step))
        s += step
    return step, table


def drop(table, s):
    step, t = table
    f = (s + 90.0) / step
    k = min(max(int(f), 0), len(t) - 2)
    return t[k] + (f - k) * (t[k + 1] - t[k])


def cliff_line(y):
    """x of the cliff's top edge (s = 0) at y: bowing out east by up to 12 m in the middle [m from X0]."""
    return 60.0 + 12.0 * math.sin(math.pi * y / 300.0) + 3.0 * math.sin(2 * math.pi * y / 90.0)


def gully_axis(s):
    return 150.0 + 18.0 * math.sin(s / 110.0)


def height(table, x, y):
    """Ground height at (x, y) [m from the south-west node]."""
    s = x - cliff_line(y)
    z = TOP - drop(table, s)
    # the gully: from the bench (s 185 m) deepening to 8 m by s 325 m, 18 m wide
    axis = gully_axis(s)
    depth = 8.0 * min(max((s - 185.0) / 140.0, 0.0), 1.0) ** 1.5
    z -= depth * math.exp(-((y - axis) / 18.0) ** 2)
    # the broad trough of the runout zone about the gully: its sides rise 4 % of the distance to the axis
    z += 0.04 * min(max((s - 275.0) / 60.0, 0.0), 1.0) * (math.hypot(y - axis, 20.0) - 20.0)
    # undulation of the talus and the runout (none on the cliff face, whose edge stays sharp)
    if s > 60:
        z += 0.6 * math.sin(x / 23.0 + 0.7) * math.sin(y / 17.0) + 0.3 * math.sin((x + 2 * y) / 9.0)
    return z


def material(x, y):
    s = x - cliff_line(y)
    return 1 if s < 57.0 else 2 if s < 315.0 else 3


def write_grid(path, ncols, nrows, xll, yll, rows, fmt, nodata):
    with open(path, 'w', newline='\n') as f:
        f.write(f'ncols {ncols}\nnrows {nrows}\nxllcorner {xll:.1f}\nyllcorner {yll:.1f}\n'
                f'cellsize {CELL:g}\nNODATA_value {nodata}\n')
        for row in rows:
            f.write(' '.join(fmt % v for v in row) + '\n')


def release_ring():
    """The strip along the cliff's top edge, y 40 .. 260 m, counter-clockwise, in map coordinates."""
    ys = [40.0 + 20.0 * k for k in range(12)]
    front = [(cliff_line(y) - RELEASE_FRONT, y) for y in ys]
    back = [(cliff_line(y) - RELEASE_BACK, y) for y in reversed(ys)]
    return [(round(X0 + x, 2), round(Y0 + y, 2)) for x, y in front + back]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..', 'examples', 'terrain')
    os.makedirs(out, exist_ok=True)
    table = drop_table()
    # DEM: node (i, j) at X0 + i CELL, Y0 + j CELL is the centre of an ESRI cell; rows north first
    dem = [[height(table, i * CELL, j * CELL) for i in range(NX)] for j in reversed(range(NY))]
    write_grid(os.path.join(out, 'dem.asc'), NX, NY, X0 - CELL / 2, Y0 - CELL / 2, dem, '%.2f', -9999)
    # classes: one per surface cell, centred in it
    cls = [[material((i + 0.5) * CELL, (j + 0.5) * CELL) for i in range(NX - 1)] for j in reversed(range(NY - 1))]
    write_grid(os.path.join(out, 'classes.asc'), NX - 1, NY - 1, X0, Y0, cls, '%d', 0)
    for name in ('dem.prj', 'classes.prj'):
        with open(os.path.join(out, name), 'w', newline='\n') as f:
            f.write(WKT + '\n')
    ring = release_ring()
    coords = ', '.join(f'[{x:.2f}, {y:.2f}]' for x, y in ring + ring[:1])
    with open(os.path.join(out, 'release.geojson'), 'w', newline='\n') as f:
        f.write('{"type": "FeatureCollection", "name": "release",\n'
                ' "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2056"}},\n'
                ' "features": [{"type": "Feature", "properties": {"name": "cliff top", "count": 10000},\n'
                f'  "geometry": {{"type": "Polygon", "coordinates": [[{coords}]]}}}}]}}\n')
    print('release polygon (inline YAML):')
    print('[' + ', '.join(f'[{x:.2f}, {y:.2f}]' for x, y in ring) + ']')


if __name__ == '__main__':
    main()
