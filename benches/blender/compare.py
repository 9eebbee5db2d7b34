"""Angles between two tangent-space normal maps (say ours and Blender's), texel by texel.

    python3 benches/blender/compare.py OURS.png BLENDER.png [--mask-from both|ours|blender]
        [--uv-mask low.obj] [--erode N] [--flip-ours-v] [--flip-ours-green]

Both PNGs are RGB or RGBA, 8- or 16-bit (decoded here with numpy alone: Pillow reads 16-bit RGB(A)
as 8-bit). A texel c (0..max) decodes to n = normalize(2 c / max - 1).

Which texels count ("covered"):
  * alpha: over the images named by --mask-from that have an alpha channel not opaque everywhere,
    texels whose alpha is nonzero in all of them (bake_pair.py's Blender map has alpha 0 outside
    the UV islands and margin; with --margin 0 its alpha is exactly Blender's coverage);
  * no such alpha in any of them: every texel except those that are background, (128, 128, 255)
    +-1 on the 8-bit scale, in both images;
  * --uv-mask OBJ additionally keeps only texels whose centre, (u, v) = ((x + .5)/W, 1 - (y + .5)/H)
    with row 0 the PNG's top, lies in a triangle of the OBJ's UV layout (this drops the margins,
    where bakers differ by design), after --erode N steps of 4-neighbour erosion (drops the texels
    on island borders, which rasterisers may assign differently).
Prints the covered count and the mean, median, 95th percentile and max angle in degrees.
"""
import argparse
import struct
import sys
import zlib

import numpy as np

from analytic import texels


def read_png(path):
    """(H, W, C) uint16 values and their maximum; RGB/RGBA, 8/16-bit, not interlaced."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat = 8, []
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + length
    if ctype not in (2, 6) or depth not in (8, 16) or interlace:
        sys.exit(f"{path}: only non-interlaced 8/16-bit RGB(A) PNGs are read")
    channels = 3 if ctype == 2 else 4
    bpp = channels * depth // 8
    rows = np.frombuffer(zlib.decompress(b"".join(idat)), np.uint8).reshape(h, w * bpp + 1)
    filt, raw = rows[:, 0], rows[:, 1:].reshape(h, w, bpp).astype(np.int32)
    # Unfiltering runs along anti-diagonals: texel (y, x) needs (y, x-1), (y-1, x), (y-1, x-1).
    out = np.zeros((h + 1, w + 1, bpp), np.int32)  # a zero row and column before the image
    for s in range(h + w - 1):
        ys = np.arange(max(0, s - w + 1), min(h, s + 1))
        xs = s - ys
        a, b, c = out[ys + 1, xs], out[ys, xs + 1], out[ys, xs]
        p = a + b - c
        pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
        paeth = np.where((pa <= pb) & (pa <= pc), a, np.where(pb <= pc, b, c))
        f = filt[ys][:, None]
        pred = np.select([f == 1, f == 2, f == 3, f == 4], [a, b, (a + b) >> 1, paeth], 0)
        out[ys + 1, xs + 1] = (raw[ys, xs] + pred) & 255
    px = out[1:, 1:].astype(np.uint16)
    if depth == 16:
        px = px.reshape(h, w, channels, 2)
        px = (px[..., 0] << 8) | px[..., 1]
    return px, (1 << depth) - 1


def uv_mask(obj_path, w, h):
    vt, tris = [], []
    for line in open(obj_path):
        word = line.split()
        if word[:1] == ["vt"]:
            vt.append((float(word[1]), float(word[2])))
        elif word[:1] == ["f"]:
            corners = [int(c.split("/")[1]) for c in word[1:]]
            corners = [k - 1 if k > 0 else len(vt) + k for k in corners]
            tris += [(corners[0], corners[i], corners[i + 1]) for i in range(1, len(corners) - 1)]
    # The texel centres inside LOW's UV triangles, rows counted up from v = 0, flipped at the end.
    rows, cols = texels(np.array(vt), np.array(tris), w, h)[:2]
    mask = np.zeros((h, w), bool)
    mask[rows, cols] = True
    return mask[::-1]


def erode(mask, n):
    for _ in range(n):
        m = mask.copy()
        m[1:] &= mask[:-1]
        m[:-1] &= mask[1:]
        m[:, 1:] &= mask[:, :-1]
        m[:, :-1] &= mask[:, 1:]
        mask = m
    return mask


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("ours")
    ap.add_argument("blender")
    ap.add_argument("--mask-from", choices=["both", "ours", "blender"], default="both")
    ap.add_argument("--uv-mask", metavar="OBJ")
    ap.add_argument("--erode", type=int, default=0)
    ap.add_argument("--flip-ours-v", action="store_true", help="flip OURS's rows first")
    ap.add_argument("--flip-ours-green", action="store_true", help="negate OURS's green (DirectX)")
    args = ap.parse_args()

    imgs = {}
    for name, path in (("ours", args.ours), ("blender", args.blender)):
        px, top = read_png(path)
        if name == "ours" and args.flip_ours_v:
            px = px[::-1]
        n = px[..., :3] * (2.0 / top) - 1.0
        if name == "ours" and args.flip_ours_green:
            n[..., 1] = -n[..., 1]
        n /= np.linalg.norm(n, axis=-1, keepdims=True).clip(1e-12)
        alpha = px[..., 3] if px.shape[-1] == 4 and px[..., 3].min() < top else None
        background = np.all(np.abs(px[..., :3] * (255.0 / top) - [128, 128, 255]) <= 1, axis=-1)
        imgs[name] = (n, alpha, background)
    (n0, _, bg0), (n1, _, bg1) = imgs["ours"], imgs["blender"]
    if n0.shape != n1.shape:
        sys.exit(f"sizes differ: {n0.shape[1]}x{n0.shape[0]} and {n1.shape[1]}x{n1.shape[0]}")
    h, w = n0.shape[:2]

    chosen = ["ours", "blender"] if args.mask_from == "both" else [args.mask_from]
    alphas = [imgs[k][1] for k in chosen if imgs[k][1] is not None]
    if alphas:
        covered = np.logical_and.reduce([a > 0 for a in alphas])
        rule = "alpha > 0 in " + " and ".join(k for k in chosen if imgs[k][1] is not None)
    else:
        covered = ~(bg0 & bg1)
        rule = "not background (128,128,255)+-1 in both"
    if args.uv_mask:
        covered &= erode(uv_mask(args.uv_mask, w, h), args.erode)
        rule += f", inside {args.uv_mask}'s UV triangles eroded {args.erode}"

    dot = np.clip(np.sum(n0 * n1, axis=-1), -1.0, 1.0)
    ang = np.degrees(np.arccos(dot))[covered]
    if ang.size == 0:
        sys.exit("no covered texels")
    worst = np.unravel_index(np.argmax(np.where(covered, np.degrees(np.arccos(dot)), -1)), (h, w))
    print(f"{w}x{h}, covered: {ang.size} texels ({100.0 * ang.size / (w * h):.1f} %; {rule})")
    print(f"angle (deg): mean {ang.mean():.3f}  median {np.median(ang):.3f}  "
          f"p95 {np.percentile(ang, 95):.3f}  max {ang.max():.3f} at (x {worst[1]}, y {worst[0]})")
    for t in (1, 2, 5, 10):
        print(f"  > {t:2d} deg: {np.mean(ang > t) * 100:.3f} %")


main()
