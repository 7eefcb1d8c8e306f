// What the page of `masssprings view` asks of the simulation, in one
// object: every request the page makes goes through `backend` (the HTTP API
// of src/app/view/api.rs, served by the masssprings process). A page that
// ran the simulation itself would replace this file and nothing else.
//
//   GET  /api/scene         once per scene: triangles, springs, pins, texture
//                           coordinates, the first view (again when
//                           status.scene_serial changes)
//   GET  /api/frame?since=S&page=ID
//                           every animation frame: the positions (binary f32;
//                           of both simulations when comparing), or 204 when
//                           nothing moved since frame serial S; it also tells
//                           the server this page is watching (the simulation
//                           runs only while some page is)
//   GET  /api/status        four times a second: steps, timings, toggles,
//                           parameters, the last steps' convergence and
//                           energies, the step in progress
//   GET  /api/image?…       without WebGL: the frame drawn by the server's
//                           own renderer for this page's camera (a PNG)
//   POST /api/command       keys, buttons, sliders, pickers, drags, stop:
//                           200 applied, 409 refused (with why), or 202
//                           accepted: it waits for the work in progress (or
//                           is it) and is applied after it
'use strict';

/** The random name this page gives itself on /api/frame. */
const PAGE_ID = Math.floor(Math.random() * 2 ** 31) + 1;

const backend = {
  /** The state: GET /api/status. */
  async status() {
    const response = await fetch('/api/status', { cache: 'no-store' });
    return response.json();
  },

  /** The scene drawn: GET /api/scene. */
  async scene() {
    const response = await fetch('/api/scene', { cache: 'no-store' });
    return response.json();
  },

  /** The frame after serial `since` (null: any), as an ArrayBuffer, or
   *  null when nothing moved. */
  async frame(since) {
    const after = since === null ? '' : `since=${since}&`;
    const response = await fetch(`/api/frame?${after}page=${PAGE_ID}`, { cache: 'no-store' });
    return response.status === 200 ? response.arrayBuffer() : null;
  },

  /** Sends a command: { status (HTTP), waits (it waits for the work in
   *  progress), answer (the new status, or { error }) }. */
  async command(body) {
    const response = await fetch('/api/command', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(body),
    });
    const waits = response.status === 202 && response.headers.get('X-Command') === 'waiting';
    return { status: response.status, ok: response.ok, waits, answer: await response.json() };
  },

  /** The address of the scene's texture (`path` from the scene), fresh
   *  for scene number `serial`. */
  textureUrl(path, serial) {
    return `${path}?scene=${serial}`;
  },

  /** The frame drawn by the server for the camera in `query`, as a Blob. */
  async image(query) {
    const response = await fetch(`/api/image?${query}`, { cache: 'no-store' });
    if (!response.ok) throw new Error(`image: ${response.status}`);
    return response.blob();
  },
};
