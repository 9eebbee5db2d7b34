"""The exact tangent-space normal map of bake_pair.py's analytic HIGH on its LOW, for judging bakers.

    python3 benches/blender/analytic.py DIR [--size N] [--extrusion 0.05] [--amp 0.02] [--freq 12]

Reads DIR/low.gltf (+ low.bin: bake_pair.py's LOW with Blender's MikkTSpace tangents, Y up) and
writes DIR/exact_normal16.png (16-bit RGBA, alpha 65535 on the texels inside LOW's UV triangles, 0
elsewhere); compares it with DIR/blender_normal16.png when that exists. Compare a map with it by
`compare.py MAP DIR/exact_normal16.png --mask-from ours` (or with --mask-from blender).

Per texel centre inside a UV triangle (glTF v runs down: row y <-> v = (y + .5)/H): P, N, T and
the sign interpolated barycentrically from LOW's vertices; a ray from P + e N/|N| along -N/|N|
(Blender's cage_extrusion e) meets HIGH's exact surface |X| = 1 + A cos(kx) cos(ky) cos(kz)
(x, y, z the unit direction; bisection); n is the surface's exact normal there (bake_pair.py's
header); the texel is the solution x of [T B N] x = n, B = sign N x T, T and N interpolated and
not normalised, normalised: that is the encoding Blender's bake matches (to 0.01 deg mean at
512^2 against the 16-bit map; dotting n with the normalised T, B, N instead is 0.1 deg mean off).
"""
import argparse, json, os, struct, zlib
import numpy as np


def gltf_mesh(d):
    g = json.load(open(os.path.join(d, "low.gltf")))
    buf = open(os.path.join(d, g["buffers"][0]["uri"]), "rb").read()

    def acc(i):
        a = g["accessors"][i]
        v = g["bufferViews"][a["bufferView"]]
        n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
        dt = {5126: np.float32, 5123: np.uint16, 5125: np.uint32}[a["componentType"]]
        off = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        return np.frombuffer(buf, dt, a["count"] * n, off).reshape(a["count"], n)

    pr = g["meshes"][0]["primitives"][0]
    at = pr["attributes"]
    f64 = lambda k: acc(at[k]).astype(np.float64)
    return f64("POSITION"), f64("NORMAL"), f64("TANGENT"), f64("TEXCOORD_0"), \
        acc(pr["indices"]).astype(np.int64).reshape(-1, 3)


def texels(uv, tris, w, h):
    """(rows, cols, triangle, barycentrics) of the texel centres inside each UV triangle."""
    out = []
    for k, t in enumerate(tris):
        p = uv[t] * [w, h]
        x0, y0 = np.floor(p.min(0)).astype(int).clip(0, [w, h])
        x1, y1 = np.ceil(p.max(0)).astype(int).clip(0, [w, h])
        X, Y = np.meshgrid(np.arange(x0, x1) + 0.5, np.arange(y0, y1) + 0.5)
        (ax, ay), (bx, by), (cx, cy) = p
        det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
        if det == 0:
            continue
        l1 = ((X - ax) * (cy - ay) - (cx - ax) * (Y - ay)) / det
        l2 = ((bx - ax) * (Y - ay) - (X - ax) * (by - ay)) / det
        m = (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
        out.append((Y[m].astype(int), X[m].astype(int), np.full(m.sum(), k),
                    np.stack([1 - l1[m] - l2[m], l1[m], l2[m]], 1)))
    return [np.concatenate(c) for c in zip(*out)]


def write_png16(path, rgba):
    h, w, _ = rgba.shape
    rows = np.concatenate([np.zeros((h, 1), np.uint8),
                           rgba.astype(">u2").view(np.uint8).reshape(h, -1)], 1)
    chunk = lambda k, b: struct.pack(">I", len(b)) + k + b + struct.pack(">I", zlib.crc32(k + b))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 6, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(rows.tobytes(), 6)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--size", type=int)
    ap.add_argument("--extrusion", type=float, default=0.05)
    ap.add_argument("--amp", type=float, default=0.02)
    ap.add_argument("--freq", type=float, default=12.0)
    args = ap.parse_args()
    A, K, E = args.amp, args.freq, args.extrusion
    size = args.size or json.load(open(os.path.join(args.dir, "blender_timings.json")))["size"]
    P, N, T, UV, I = gltf_mesh(args.dir)
    ys, xs, k, bary = texels(UV, I, size, size)
    tri, w = I[k], bary[..., None]
    p, nrm, tan = (P[tri] * w).sum(1), (N[tri] * w).sum(1), (T[tri][..., :3] * w).sum(1)
    nh = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
    origin = p + E * nh

    def outside(t):  # the ray point is outside HIGH
        x = origin - t[:, None] * nh
        r = np.linalg.norm(x, axis=1)
        return r - 1 - A * np.prod(np.cos(K * x / r[:, None]), axis=1) > 0

    lo, hi = np.zeros(len(p)), np.full(len(p), E + 2 * A + 0.05)
    for _ in range(50):
        mid = (lo + hi) / 2
        o = outside(mid)
        lo, hi = np.where(o, mid, lo), np.where(o, hi, mid)
    x = origin - lo[:, None] * nh
    r = np.linalg.norm(x, axis=1)
    u = x / r[:, None]
    c, s = np.cos(K * u), np.sin(K * u)
    grad = -A * K * np.stack([s[:, 0] * c[:, 1] * c[:, 2], c[:, 0] * s[:, 1] * c[:, 2],
                              c[:, 0] * c[:, 1] * s[:, 2]], 1)
    n = u - (grad - (grad * u).sum(1, keepdims=True) * u) / r[:, None]
    bit = T[tri][:, 0, 3:4] * np.cross(nrm, tan)
    e = np.linalg.solve(np.stack([tan, bit, nrm], 2), n[..., None])[..., 0]
    e /= np.linalg.norm(e, axis=1, keepdims=True)

    img = np.zeros((size, size, 4), np.uint16)
    img[..., :3] = [32768, 32768, 65535]
    img[ys, xs, :3] = np.round((e * 0.5 + 0.5) * 65535).clip(0, 65535)
    img[ys, xs, 3] = 65535
    out = os.path.join(args.dir, "exact_normal16.png")
    write_png16(out, img)
    print(f"{out}: {len(ys)} texels inside LOW's UV triangles")
    ref_path = os.path.join(args.dir, "blender_normal16.png")
    if os.path.exists(ref_path):
        src = open(os.path.join(os.path.dirname(__file__), "compare.py")).read()
        ns = {}
        exec(src.replace("\nmain()\n", "\n"), ns)
        ref, top = ns["read_png"](ref_path)
        ref = ref[ys, xs, :3] * (2.0 / top) - 1
        ref /= np.linalg.norm(ref, axis=1, keepdims=True)
        a = np.degrees(np.arccos(np.clip((ref * e).sum(1), -1, 1)))
        print(f"blender_normal16.png vs exact (deg): mean {a.mean():.4f}  median "
              f"{np.median(a):.4f}  p95 {np.percentile(a, 95):.4f}  max {a.max():.4f}")


if __name__ == "__main__":
    main()
