"""The bake benchmarks' models, written as OBJ text (benches/bake.sh and web/bench.py --bake)."""
import math


def sphere(path, segments, rings, amplitude, uvs=True, normals=False):
    """A UV sphere of `segments` × `rings` as Blender lays it out (each ring's seam vertex twice in
    UV, the poles a UV apiece per segment), bumped by `amplitude`; with `normals` its unbumped
    normals (`vn`), and without `uvs` the faces `f v//vn` of a sculpt's export."""
    with open(path, 'w') as f:
        points = [(0.0, 0.0)] + [(math.pi * r / rings, 2 * math.pi * s / segments)
                                 for r in range(1, rings) for s in range(segments)] + [(math.pi, 0.0)]
        for theta, phi in points:
            u = (math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi))
            r = 1 + amplitude * math.cos(12 * u[0]) * math.cos(12 * u[1]) * math.cos(12 * u[2])
            f.write('v %.7f %.7f %.7f\n' % (u[0] * r, u[1] * r, u[2] * r))
            if normals:
                f.write('vn %.7f %.7f %.7f\n' % u)
        if uvs:
            for r in range(1, rings):
                for s in range(segments + 1):
                    f.write('vt %.7f %.7f\n' % (s / segments, 1 - r / rings))
            for v in (1.0, 0.0):
                for s in range(segments):
                    f.write('vt %.7f %.1f\n' % ((s + 0.5) / segments, v))
        last = len(points)
        ring_uvs = (rings - 1) * (segments + 1)

        def vertex(r, s):
            return 1 if r == 0 else last if r == rings else 2 + (r - 1) * segments + s % segments

        def uv(r, s):
            if r == 0:
                return ring_uvs + s + 1
            if r == rings:
                return ring_uvs + segments + s + 1
            return (r - 1) * (segments + 1) + s + 1

        def corner(r, s, pole):
            # A pole's corner takes its segment's own UV.
            v = vertex(r, s)
            t = '%d' % uv(r, pole if r in (0, rings) else s) if uvs else ''
            return '%d/%s/%d' % (v, t, v) if normals else '%d/%s' % (v, t) if uvs else '%d' % v

        for s in range(segments):
            f.write('f %s %s %s\n' % (corner(0, s, s), corner(1, s, s), corner(1, s + 1, s)))
            for r in range(1, rings - 1):
                a, b = corner(r, s, s), corner(r + 1, s, s)
                c, d = corner(r + 1, s + 1, s), corner(r, s + 1, s)
                f.write('f %s %s %s\nf %s %s %s\n' % (a, b, c, a, c, d))
            f.write('f %s %s %s\n' % (corner(rings - 1, s, s), corner(rings, s, s),
                                      corner(rings - 1, s + 1, s)))
