"""A hard-surface bake pair as a modeller hands it over, written as OBJ (plain python3, no Blender):

    python3 benches/blender/cube_pair.py DIR [--grid 180] [--turn none|two|three] [--amp 0.03]

  DIR/low.obj   LOW: a cube of side 2 at the origin, 12 triangles, flat normals, its six faces laid
                out in a 3 x 2 UV atlas (each face one cell, 2 % of a cell's side left around it).
  DIR/high.obj  HIGH: the same cube with bumps, each face a GRID x GRID grid of quads (two triangles
                each: 388,800 triangles at 180), pushed out along its face's normal by
                h(s, t) = A sin^2(pi B s) sin^2(pi B t) (B = 6 bumps a side; h and its slope are 0 on
                the cube's edges, so the faces meet), the exact normals of that surface per vertex.
                Its faces are split at the cube's edges (hard edges), as a hard-surface export is.

--turn turns both about the origin by the same rotation: `two` about X by 20 degrees then Y by 30
(the normals of the two faces on X keep a zero component), `three` then about Z by 15 as well.
`none`: every face along an axis, the case that breaks a slab test's infinities.

The sculpt's file (`f v//vn`, no UVs) is written with --no-uvs: `high.obj` without `vt`.
"""
import argparse
import math
import os


def rotation(turn):
    def rx(a):
        c, s = math.cos(a), math.sin(a)
        return [[1, 0, 0], [0, c, -s], [0, s, c]]

    def ry(a):
        c, s = math.cos(a), math.sin(a)
        return [[c, 0, s], [0, 1, 0], [-s, 0, c]]

    def rz(a):
        c, s = math.cos(a), math.sin(a)
        return [[c, -s, 0], [s, c, 0], [0, 0, 1]]

    def mul(a, b):
        return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]

    m = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    if turn in ("two", "three"):
        m = mul(ry(math.radians(30)), rx(math.radians(20)))
    if turn == "three":
        m = mul(rz(math.radians(15)), m)
    return lambda v: tuple(sum(m[i][k] * v[k] for k in range(3)) for i in range(3))


# Each face: its normal, and the directions of s and t across it (s x t = normal), and its atlas cell.
FACES = [
    ((1, 0, 0), (0, 0, -1), (0, 1, 0), (0, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0), (1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, -1), (2, 0)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1), (0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0), (1, 1)),
    ((0, 0, -1), (-1, 0, 0), (0, 1, 0), (2, 1)),
]


def atlas_uv(cell, s, t):
    pad = 0.02
    cu, cv = cell
    return ((cu + pad + s * (1 - 2 * pad)) / 3, (cv + pad + t * (1 - 2 * pad)) / 2)


def point(face, s, t, h):
    n, a, b, _ = face
    return tuple(n[i] + (2 * s - 1) * a[i] + (2 * t - 1) * b[i] + h * n[i] for i in range(3))


def write_low(path, turn):
    with open(path, "w") as f:
        f.write("# a cube, 12 triangles, a 3 x 2 UV atlas\no LOW\n")
        for face in FACES:
            for s, t in ((0, 0), (1, 0), (1, 1), (0, 1)):
                f.write("v %.7f %.7f %.7f\n" % turn(point(face, s, t, 0.0)))
        for face in FACES:
            for s, t in ((0, 0), (1, 0), (1, 1), (0, 1)):
                f.write("vt %.7f %.7f\n" % atlas_uv(face[3], s, t))
        for face in FACES:
            f.write("vn %.7f %.7f %.7f\n" % turn(face[0]))
        f.write("s off\n")
        for k in range(6):
            c = [4 * k + i + 1 for i in range(4)]
            n = k + 1
            f.write("f %d/%d/%d %d/%d/%d %d/%d/%d\n" % (c[0], c[0], n, c[1], c[1], n, c[2], c[2], n))
            f.write("f %d/%d/%d %d/%d/%d %d/%d/%d\n" % (c[0], c[0], n, c[2], c[2], n, c[3], c[3], n))


def write_high(path, turn, grid, amp, uvs):
    bumps = 6
    k = math.pi * bumps
    with open(path, "w") as f:
        f.write("# a cube with bumps, %d triangles\no HIGH\n" % (12 * grid * grid))
        side = grid + 1
        normals = []
        uv_lines = []
        for face in FACES:
            n, a, b, cell = face
            for j in range(side):
                t = j / grid
                for i in range(side):
                    s = i / grid
                    h = amp * math.sin(k * s) ** 2 * math.sin(k * t) ** 2
                    f.write("v %.7f %.7f %.7f\n" % turn(point(face, s, t, h)))
                    # dh/ds and dh/dt; a unit of s is 2 units along a (and t along b).
                    hs = amp * 2 * math.sin(k * s) * math.cos(k * s) * k * math.sin(k * t) ** 2
                    ht = amp * 2 * math.sin(k * t) * math.cos(k * t) * k * math.sin(k * s) ** 2
                    v = [n[m] - hs / 2 * a[m] - ht / 2 * b[m] for m in range(3)]
                    length = math.sqrt(sum(c * c for c in v))
                    normals.append(turn(tuple(c / length for c in v)))
                    if uvs:
                        uv_lines.append("vt %.7f %.7f\n" % atlas_uv(cell, s, t))
        f.writelines(uv_lines)
        f.writelines("vn %.7f %.7f %.7f\n" % n for n in normals)
        f.write("s 1\n")
        for fi in range(6):
            base = fi * side * side + 1
            for j in range(grid):
                for i in range(grid):
                    c = [base + j * side + i, base + j * side + i + 1,
                         base + (j + 1) * side + i + 1, base + (j + 1) * side + i]
                    if uvs:
                        w = ["%d/%d/%d" % (x, x, x) for x in c]
                    else:
                        w = ["%d//%d" % (x, x) for x in c]
                    f.write("f %s %s %s\nf %s %s %s\n" % (w[0], w[1], w[2], w[0], w[2], w[3]))


def main():
    p = argparse.ArgumentParser(prog="cube_pair.py")
    p.add_argument("dir")
    p.add_argument("--grid", type=int, default=180)
    p.add_argument("--turn", default="none", choices=["none", "two", "three"])
    p.add_argument("--amp", type=float, default=0.03)
    p.add_argument("--no-uvs", action="store_true", help="HIGH without vt (f v//vn)")
    args = p.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    turn = rotation(args.turn)
    write_low(os.path.join(args.dir, "low.obj"), turn)
    write_high(os.path.join(args.dir, "high.obj"), turn, args.grid, args.amp, not args.no_uvs)


main()
