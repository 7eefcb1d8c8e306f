// What the viewer's page asks of the simulation, when the page runs it
// itself: the same object as src/app/view/assets/backend.js (the HTTP API
// of `masssprings view`), which the static build (src/web/build.sh)
// replaces with this file. The simulation runs in a Web Worker (host.mjs:
// the library compiled to WebAssembly, masssprings.wasm, and what the
// viewer's server does around it), so that a step never freezes the page.
//
// The worker sends the scene, each frame and the status as they change;
// this object keeps the latest and hands them to the page when it asks,
// as the server answers its polls. Commands go to the worker and come back
// answered 200, 409 (refused, with why) or 400, or 202 when sent during
// work the worker announced as long (it is applied after that work).
//
// Stop: a step or a setup that may be long is announced with a snapshot
// of the state before it; ■ stop (Esc) then ends the worker at once,
// whatever the work was doing, and starts a fresh one from that snapshot
// (the module compiled once, here, is handed to each worker). Shorter
// work ends within a tenth of a second, and the stop is applied after it.
'use strict';

/** The memory the page gives the simulation: a quarter of the device's
 *  (navigator.deviceMemory, where the browser tells it; 4 GB where not),
 *  at most 2 GB. The module's limit is half of it (src/memory.rs). */
function memoryBudget() {
  const deviceGigabytes = navigator.deviceMemory || 4;
  return Math.min(2 ** 31, (deviceGigabytes * 2 ** 30) / 4);
}

const backend = (() => {
  const answered = new Map(); // command id → resolve
  const dropped = []; // the user's scenes, [[{ name, bytes }]], for a fresh worker
  let worker = null;
  let nextId = 1;
  let latest = { status: null, scene: null, frame: null, texture: null, textureSerial: -1, textureUrl: null };
  let work = null; // { what, since, snapshot } while the worker says it works
  let ready = null;
  let lastWatching = 0;
  let waiting = 0; // commands sent during long work, not answered yet
  const compiled = compile();

  /** The WebAssembly module, compiled once for every worker. */
  async function compile() {
    const response = await fetch('masssprings.wasm');
    if (!response.ok) throw new Error(`masssprings.wasm: ${response.status} ${response.statusText}`);
    return WebAssembly.compile(await response.arrayBuffer());
  }

  function startWorker(restore = null) {
    let started;
    let failed;
    ready = new Promise((resolve, reject) => { started = resolve; failed = reject; });
    worker = new Worker('host.mjs', { type: 'module' });
    worker.onmessage = ({ data }) => take(data, started, failed);
    worker.onerror = (event) => failed(new Error(event.message || 'the simulation\'s worker failed to start'));
    compiled.then(
      (wasm) => worker.postMessage({ type: 'start', wasm, budget: memoryBudget(), dropped, restore }),
      failed,
    );
  }

  function take(data, started, failed) {
    switch (data.type) {
      case 'status':
        latest.status = data.status;
        started();
        break;
      case 'scene':
        latest.scene = data.scene;
        latest.texture = data.texture;
        break;
      case 'frame':
        latest.frame = data.bytes;
        break;
      case 'busy':
        work = { what: data.what, since: performance.now(), snapshot: data.snapshot };
        break;
      case 'idle':
        work = null;
        break;
      case 'answer': {
        const resolve = answered.get(data.id);
        answered.delete(data.id);
        if (resolve) resolve(data);
        break;
      }
      case 'failed':
        failed(new Error(data.message));
        latest.status = latest.status && { ...latest.status, error: data.message };
        break;
      default:
    }
  }

  /** The latest status, with the work in progress and the commands
   *  waiting for it. */
  function decorated() {
    const s = latest.status;
    if (!s) return s;
    return {
      ...s,
      busy: work ? work.what : null,
      busy_ms: work ? performance.now() - work.since : null,
      queued: waiting,
    };
  }

  /** Sends `message` (a command, or files to open) and waits for its answer. */
  function ask(message) {
    const id = nextId++;
    return new Promise((resolve) => {
      answered.set(id, resolve);
      worker.postMessage({ ...message, id });
    });
  }

  /** Sends a command during long work: answered after it. */
  function queue(body) {
    waiting += 1;
    ask({ type: 'command', body, detached: true }).finally(() => { waiting -= 1; });
  }

  /** Ends the worker in its long work and starts a fresh one from the
   *  snapshot taken before it; the page is told at once (paused, the note
   *  saying what was stopped), and its next questions wait for the fresh
   *  worker. */
  function stopWork() {
    const { what, since, snapshot } = work;
    const seconds = ((performance.now() - since) / 1000).toFixed(1);
    const step = /^step (\d+)$/.exec(what);
    const note = step
      ? `step ${step[1]} cancelled after ${seconds} s: the simulation stays at step ${step[1] - 1}`
      : `${what}: cancelled after ${seconds} s; nothing changed`;
    worker.terminate();
    work = null;
    for (const [id, resolve] of answered) {
      answered.delete(id); // the work stopped, and what was sent during it
      resolve({ code: 409, answer: { error: note } });
    }
    latest.status = { ...latest.status, animating: false, note };
    startWorker({ ...snapshot, note });
  }

  startWorker();

  return {
    /** The state, as GET /api/status answers it (while a fresh worker
     *  starts after a stop, the state it starts from). */
    async status() {
      if (!latest.status) await ready;
      return decorated();
    },

    /** The scene drawn, as GET /api/scene answers it. */
    async scene() {
      await ready;
      return latest.scene;
    },

    /** The frame after serial `since` (null: any), as an ArrayBuffer, or
     *  null when nothing moved; it also tells the worker the page is
     *  watching (it steps only while one is). */
    async frame(since) {
      const now = performance.now();
      if (now - lastWatching > 250) {
        lastWatching = now;
        worker.postMessage({ type: 'watching' });
      }
      const bytes = latest.frame;
      if (!bytes || (since !== null && new DataView(bytes).getUint32(4, true) === since)) return null;
      return bytes;
    },

    /** Sends a command: { status, ok, waits, answer }, as the HTTP backend. */
    async command(body) {
      await ready;
      if (body.command === 'cancel' && work && work.snapshot) {
        stopWork();
        return { status: 200, ok: true, waits: false, answer: decorated() };
      }
      if (work && work.snapshot) {
        // long work in progress: applied after it, refused then in the note
        queue(body);
        return { status: 202, ok: true, waits: true, answer: decorated() };
      }
      const { code, answer } = await ask({ type: 'command', body });
      return { status: code, ok: code === 200, waits: false, answer: code === 200 ? decorated() : answer };
    },

    /** The address of the scene's texture: its PNG's bytes as a blob. */
    textureUrl(path, serial) {
      if (latest.textureSerial !== serial || !latest.textureUrl) {
        if (latest.textureUrl) URL.revokeObjectURL(latest.textureUrl);
        latest.textureUrl = URL.createObjectURL(new Blob([latest.texture], { type: 'image/png' }));
        latest.textureSerial = serial;
      }
      return latest.textureUrl;
    },

    /** Without WebGL the server draws the frames; a page has no renderer of
     *  its own. */
    async image() {
      throw new Error('this page draws with WebGL, which this browser does not give it');
    },

    /** Opens the user's own scene, `files` (File objects: its JSON, the OBJ
     *  and the PNG it names): { ok, answer } as a command's, the error in
     *  the command line's words. */
    async openFiles(files) {
      await ready;
      const given = await Promise.all(Array.from(files, async (file) => ({
        name: file.name, bytes: new Uint8Array(await file.arrayBuffer()),
      })));
      const { code, answer } = await ask({ type: 'open', files: given });
      if (code === 200) {
        const json = given.find((file) => file.name.toLowerCase().endsWith('.json'));
        const index = dropped.findIndex((scene) => scene.some((file) => file.name === json.name));
        dropped[index >= 0 ? index : dropped.length] = given;
      }
      return { ok: code === 200, answer: code === 200 ? decorated() : answer };
    },
  };
})();
