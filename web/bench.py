#!/usr/bin/env python3
"""The page's budgets in real time (BENCHMARKS.md): Chromium headless on SwiftShader, driven through
its DevTools protocol (web/page.py: no virtual time, no extra Python package).

    python3 web/bench.py http://127.0.0.1:8000 [frames]
    python3 web/bench.py http://127.0.0.1:8000 --bake [rounds]

The first prints, per scene, when the first frame was drawn since navigation began and the median
frame time (each frame drawn to completion) over N frames. The second times the page's bake (its
Web Worker) against `tutorial13 bake` on one core (`taskset -c 0`, so the command bakes on one
thread) in the same run, round after round, on pairs shaped as users bring them: a sculpt exported
without UVs onto a UV sphere, at 1 and 4 × 4 rays a texel, and a bumpy hard-surface cube turned
about three axes onto a 12-triangle cube with a 3 × 2 atlas. The pairs are written into the served
folder's drops/ ($TUTORIAL13_WEB_DIR, default target/web); the command is target/release/tutorial13
(`cargo build --release` first). Each round also says whether the page's PNG is the command's,
byte for byte.
"""
import math, os, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, 'web'), os.path.join(ROOT, 'benches')]
from page import Page  # noqa: E402
from pairs import sphere  # noqa: E402


def frames(base, count):
    for scene in ['cylinder', 'sprite', 'cube', 'wall']:
        page = Page(f'{base}/index.html?scene={scene}&panel=off&frames={count}')
        try:
            data = {}
            deadline = time.time() + 120
            while time.time() < deadline:
                data = page.evaluate('document.getElementById("canvas") && Object.assign({'
                                     ' message: document.getElementById("message").className == "error"'
                                     '   ? document.getElementById("message").textContent : ""},'
                                     ' document.getElementById("canvas").dataset)') or {}
                if data.get('message', '').strip() or int(data.get('frames', 0)) >= count:
                    break
                time.sleep(0.05)
            if data.get('message', '').strip():
                print(f'{scene}: the page says: {data["message"]}', flush=True)
            elif int(data.get('frames', 0)) >= count:
                print(f'{scene}: first frame {data["firstFrameMs"]} ms after navigation began; '
                      f'{data["frameMs"]} ms/frame (median of {count}, each to a one-texel read-back)',
                      flush=True)
            else:
                print(f'{scene}: no {count} frames within 120 s', flush=True)
        finally:
            page.close()


def cube(path, grid, amplitude):
    """A cube of side 2 turned about three axes: each face a `grid` × `grid` quad grid bumped out
    by `amplitude` (HIGH, no UVs, its normals computed when read), or with `grid` 1 and no bumps
    the 12-triangle LOW with a 3 × 2 UV atlas."""
    turn = rotation(0.35, 0.6, 0.25)
    faces = [((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
             ((0, 1, 0), (1, 0, 0), (0, 0, -1)), ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
             ((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0))]
    lines, count = [], 0
    for f, (n, u, v) in enumerate(faces):
        first = count + 1
        for j in range(grid + 1):
            for i in range(grid + 1):
                a, b = 2 * i / grid - 1, 2 * j / grid - 1
                h = amplitude * math.sin(5 * math.pi * a) * math.sin(5 * math.pi * b) if grid > 1 else 0
                p = [n[k] * (1 + h) + u[k] * a + v[k] * b for k in range(3)]
                lines.append('v %.7f %.7f %.7f' % tuple(turn(p)))
                count += 1
                if grid == 1:
                    # Face f's cell of the 3 × 2 atlas, 1 % of it left around the island.
                    lines.append('vt %.7f %.7f' % ((f % 3 + 0.02 + 0.96 * i) / 3, (f // 3 + 0.02 + 0.96 * j) / 2))
        for j in range(grid):
            for i in range(grid):
                k = first + j * (grid + 1) + i
                quad = [k, k + 1, k + grid + 2, k + grid + 1]
                corner = (lambda q: '%d/%d' % (q, q)) if grid == 1 else str
                lines.append('f %s %s %s\nf %s %s %s' % (*map(corner, quad[:3]), *map(corner, [quad[0], quad[2], quad[3]])))
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def rotation(x, y, z):
    def turn(p):
        for axis, angle in ((0, x), (1, y), (2, z)):
            c, s = math.cos(angle), math.sin(angle)
            i, j = [k for k in range(3) if k != axis]
            p = list(p)
            p[i], p[j] = c * p[i] - s * p[j], s * p[i] + c * p[j]
        return p
    return turn


def bake(base, rounds):
    served = os.environ.get('TUTORIAL13_WEB_DIR', os.path.join(ROOT, 'target/web'))
    drops = os.path.join(served, 'drops')
    os.makedirs(drops, exist_ok=True)
    command = os.path.join(ROOT, 'target/release/tutorial13')
    sphere(os.path.join(drops, 'bench_sculpt.obj'), 512, 256, 0.02, uvs=False, normals=True)
    sphere(os.path.join(drops, 'bench_sphere.obj'), 32, 16, 0.0, normals=True)
    cube(os.path.join(drops, 'bench_cube_high.obj'), 120, 0.01)
    cube(os.path.join(drops, 'bench_cube.obj'), 1, 0.0)
    jobs = [('sculpt (261,120 triangles, no UVs) onto a 32 x 16 sphere, 1024², 1 ray',
             'bench_sculpt.obj', 'bench_sphere.obj', 1),
            ('the same, 4 x 4 rays', 'bench_sculpt.obj', 'bench_sphere.obj', 4),
            ('bumpy cube (172,800 triangles) onto a 12-triangle cube, turned, 1024², 1 ray',
             'bench_cube_high.obj', 'bench_cube.obj', 1)]
    out = tempfile.mkdtemp()
    for name, high, low, samples in jobs:
        print(name, flush=True)
        for round in range(rounds):
            native_png = os.path.join(out, 'native.png')
            start = time.perf_counter()
            done = subprocess.run(['taskset', '-c', '0', command, 'bake', high, low, '-o', native_png,
                                   '--size', '1024', '--samples', str(samples)],
                                  cwd=drops, capture_output=True)
            native = time.perf_counter() - start
            if done.returncode != 0:
                sys.exit(f'tutorial13 bake failed: {done.stderr.decode()}')
            page = Page(f'{base}/index.html?scene=cube&panel=off&frames=1000000&bake-high={high}'
                        f'&bake-low={low}&bake-set=bake-size:1024,bake-samples:{samples}')
            try:
                if not page.wait('["done", "failed"].includes(document.getElementById("bake").dataset.state)'
                                 ' && (document.getElementById("bake").dataset.state != "done"'
                                 '     || document.getElementById("bake-map"))', 900):
                    sys.exit('the page did not bake within 900 s')
                data = page.evaluate('Object.assign({ message: document.getElementById("message").textContent,'
                                     ' map: (document.getElementById("bake-map") || {}).textContent },'
                                     ' document.getElementById("bake").dataset)')
            finally:
                page.close()
            if data['state'] != 'done':
                sys.exit(f'the page says: {data["message"]}')
            with open(native_png, 'rb') as f:
                same = bytes.fromhex(data['map']) == f.read()
            worker, total = int(data['workerMs']) / 1000, int(data['bakeMs']) / 1000
            start_frame, end_frame = map(int, data['framesDuring'].split())
            print(f'  round {round + 1}: command on one core {native:.2f} s; page: worker {worker:.2f} s '
                  f'({worker / native:.2f}x), Bake to map {total:.2f} s ({total / native:.2f}x); '
                  f'{end_frame - start_frame} frames drawn meanwhile; the PNG '
                  f'{"is" if same else "is NOT"} the command\'s byte for byte', flush=True)


if __name__ == '__main__':
    base = sys.argv[1].rstrip('/')
    if len(sys.argv) > 2 and sys.argv[2] == '--bake':
        bake(base, int(sys.argv[3]) if len(sys.argv) > 3 else 3)
    else:
        frames(base, int(sys.argv[2]) if len(sys.argv) > 2 else 100)
