// The page's bake, off its main thread: this Web Worker (a module worker) loads the page's own
// module (tutorial13.js, whose start does nothing here), warms it up with a small bake, and runs
// its `bake` on the files and arguments the bake panel posts: { files: [[path, bytes]...],
// args: [...] }. It answers { progress: [stage, share] } as the bake goes, then
// { done: { map, report, seconds } } or { error }.
// Cancel terminates the worker (no shared memory: a plain file server sends no cross-origin
// isolation headers), so one worker bakes once.
import init, { bake, provide_file, warm_up } from './tutorial13.js';

// A small bake first, so that the browser has its best code for the user's (web/src/bake.rs).
const loaded = init().then(() => warm_up());
self.onmessage = async ({ data }) => {
  try {
    await loaded;
    for (const [path, bytes] of data.files) provide_file(path, bytes);
    const done = bake(data.args, (stage, share) => self.postMessage({ progress: [stage, share] }));
    self.postMessage({ done }, [done.map.buffer]);
  } catch (e) {
    // A Rust error is its one line; anything else (a trap after a panic, whose line the panic
    // hook posted first) is said as it is.
    self.postMessage({ error: typeof e === 'string' ? e : 'internal error: ' + e });
  }
};
