// What the browser tests share: starting `masssprings view` on a free
// port, launching Debian's Chromium (headless, driven by playwright-core),
// and reading the viewer's status and the canvas.
//
// Environment: MASSSPRINGS_BIN (the binary), CHROMIUM (the browser).
import assert from 'node:assert/strict';
import { execFileSync, spawn } from 'node:child_process';
import http from 'node:http';
import { createInterface } from 'node:readline';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
export const binary = process.env.MASSSPRINGS_BIN ?? path.join(root, 'target/debug/masssprings');
export const outputFolder = path.join(root, 'target/browser');

// The launch flags of the machine notes: no sandbox (root), no GPU, and no
// background connections (the network is closed). WebGL runs on SwiftShader.
export const CHROMIUM_FLAGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
];

/** Chromium without WebGL: the page falls back to the server's images. */
export const NO_WEBGL_FLAGS = ['--disable-webgl', '--disable-3d-apis'];

/** Runs `masssprings simulate SCENE --steps N --out FOLDER` (the frames
 *  a program writes, for --frames). */
export function writeFrames(scene, steps, folder) {
  execFileSync(binary, ['simulate', scene, '--steps', String(steps), '--out', folder, '--force'], { stdio: 'ignore' });
}

/** Starts `masssprings view SCENE --port 0 FLAGS…` and reads the URL it
 *  prints. */
export async function startViewer(scene, flags = []) {
  const child = spawn(binary, ['view', scene, '--port', '0', ...flags], { stdio: ['ignore', 'pipe', 'inherit'] });
  const lines = createInterface({ input: child.stdout });
  const firstLine = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error('no URL within 30 s')), 30000);
    lines.once('line', (line) => { clearTimeout(timer); resolve(line); });
    child.once('exit', (code) => reject(new Error(`viewer exited with ${code}`)));
  });
  assert.match(firstLine, /^http:\/\/127\.0\.0\.1:\d+\/$/);
  return { child, url: firstLine };
}

/** Stops a viewer started by startViewer (SIGINT, then SIGKILL after 5 s). */
export async function stopViewer(child) {
  if (!child || child.exitCode !== null) return;
  const exited = new Promise((resolve) => child.once('exit', resolve));
  child.kill('SIGINT');
  const timer = setTimeout(() => child.kill('SIGKILL'), 5000);
  await exited;
  clearTimeout(timer);
}

/** A viewer and a Chromium page showing it, with the page's errors and any
 *  request that leaves the viewer collected. */
export class Session {
  constructor() {
    this.pageErrors = [];
    this.foreignRequests = [];
  }

  /** Starts the viewer of `scene` and opens it at `viewport`
   *  (`touch`: as a phone's browser, with a touch screen). */
  async open(scene, { flags = [], viewport = { width: 1400, height: 900 }, chromiumFlags = [], touch = false } = {}) {
    ({ child: this.viewer, url: this.url } = await startViewer(scene, flags));
    await this.launch({ viewport, chromiumFlags, touch });
    await this.page.goto(this.url);
    return this;
  }

  /** Launches Chromium with a page at `viewport`, collecting the page's
   *  errors and any request that does not go to `this.url`. */
  async launch({ viewport, chromiumFlags, touch }) {
    fs.mkdirSync(outputFolder, { recursive: true });
    this.userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'masssprings-chromium-'));
    this.browser = await chromium.launchPersistentContext(this.userDataDir, {
      executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
      headless: true,
      args: [...CHROMIUM_FLAGS, ...chromiumFlags],
      viewport,
      ...(touch ? { hasTouch: true, isMobile: true } : {}),
    });
    this.page = this.browser.pages()[0] ?? await this.browser.newPage();
    this.page.on('pageerror', (error) => this.pageErrors.push(String(error)));
    this.page.on('console', (message) => { if (message.type() === 'error') this.pageErrors.push(message.text()); });
    this.page.on('request', (request) => {
      const address = request.url();
      const local = address.startsWith(this.url) || address.startsWith('data:') || address.startsWith('blob:');
      if (!local) this.foreignRequests.push(address);
    });
  }

  async close() {
    await this.browser?.close();
    if (this.userDataDir) fs.rmSync(this.userDataDir, { recursive: true, force: true });
    await stopViewer(this.viewer);
  }

  async status() {
    const response = await fetch(`${this.url}api/status`);
    return response.json();
  }

  /** The viewer process's resident memory, in MB (Linux). */
  residentMegabytes() {
    const status = fs.readFileSync(`/proc/${this.viewer.pid}/status`, 'utf8');
    return Number(status.match(/VmRSS:\s+(\d+) kB/)[1]) / 1024;
  }

  /** Polls `condition(status)` until it holds (or fails after `ms`). */
  async waitForStatus(condition, what, ms = 10000) {
    const deadline = Date.now() + ms;
    for (;;) {
      const s = await this.status();
      if (condition(s)) return s;
      if (Date.now() > deadline) throw new Error(`timed out waiting for ${what}: ${JSON.stringify(s)}`);
      await new Promise((resolve) => setTimeout(resolve, 50));
    }
  }

  /** Posts a command as the page would, from the test. */
  async command(body) {
    const response = await fetch(`${this.url}api/command`, {
      method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
    });
    return { status: response.status, body: await response.json() };
  }

  /** Waits until the page is ready and has drawn the scene. */
  async ready() {
    await this.page.waitForFunction(() => window.viewer.ready && window.viewer.framesReceived > 0
      && window.viewer.framesDrawn > 0 && window.viewer.textureLoaded, null, { timeout: 30000 });
  }

  /** The share of canvas pixels that differ clearly from the background
   *  gradient of that row, and a cheap fingerprint of the image. */
  canvasContent() {
    return this.page.evaluate(canvasContentInPage);
  }

  /** Where every vertex of simulation `set` lands on the page (CSS
   *  pixels): the smallest box around them. */
  projectedBox(set = 0) {
    return this.page.evaluate((which) => {
      const xs = [];
      const ys = [];
      for (let i = 0; i < window.viewer.state.scene.n; i++) {
        const p = window.viewer.screenPositionOf(i, which);
        xs.push(p.x);
        ys.push(p.y);
      }
      return { left: Math.min(...xs), right: Math.max(...xs), top: Math.min(...ys), bottom: Math.max(...ys) };
    }, set);
  }
}

/** In the page: canvasContent's measurement. */
function canvasContentInPage() {
  const source = document.getElementById('view');
  const copy = document.createElement('canvas');
  copy.width = source.width;
  copy.height = source.height;
  const context = copy.getContext('2d');
  context.drawImage(source, 0, 0);
  const { data, width, height } = context.getImageData(0, 0, copy.width, copy.height);
  const { backgroundTop: top, backgroundBottom: bottom } = window.viewer.look;
  let foreground = 0;
  let fingerprint = 0;
  for (let y = 0; y < height; y++) {
    const h = 1 - (y + 0.5) / height; // 1 at the top row
    const expected = [0, 1, 2].map((k) => 255 * (bottom[k] + (top[k] - bottom[k]) * h));
    for (let x = 0; x < width; x++) {
      const i = 4 * (y * width + x);
      const far = [0, 1, 2].some((k) => Math.abs(data[i + k] - expected[k]) > 30);
      if (far) foreground++;
      fingerprint = (fingerprint * 31 + data[i] + 7 * data[i + 1] + 13 * data[i + 2]) % 1000000007;
    }
  }
  return { foreground: foreground / (width * height), fingerprint };
}

/** The types a static host gives the page's files. */
const STATIC_TYPES = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.css': 'text/css', '.wasm': 'application/wasm', '.json': 'application/json', '.png': 'image/png',
  '.obj': 'text/plain',
};

/** Serves `folder` as any static host does (GET of its files, 404 for
 *  anything else), recording every path asked for. */
export async function serveFolder(folder) {
  const requests = [];
  const server = http.createServer((request, response) => {
    requests.push(request.url);
    let wanted = decodeURIComponent(new URL(request.url, 'http://host').pathname);
    if (wanted.endsWith('/')) wanted += 'index.html';
    const file = path.join(folder, wanted);
    if (request.method !== 'GET' || !file.startsWith(folder) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      response.writeHead(404);
      response.end();
      return;
    }
    response.writeHead(200, { 'Content-Type': STATIC_TYPES[path.extname(file)] ?? 'application/octet-stream' });
    fs.createReadStream(file).pipe(response);
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  return { server, requests, url: `http://127.0.0.1:${server.address().port}/` };
}

/** The static build's folder (src/web/build.sh). */
export const staticFolder = process.env.MASSSPRINGS_WEB ?? path.join(root, 'target/web');

/** The page of the static build (the simulation in the page, no server
 *  but a static one) in Chromium: the same questions as a Session, asked
 *  of the page's own backend. */
export class StaticSession extends Session {
  /** Serves the static build and opens it at `viewport`. */
  async open({ viewport = { width: 1400, height: 900 }, chromiumFlags = [] } = {}) {
    ({ server: this.server, requests: this.requests, url: this.url } = await serveFolder(staticFolder));
    await this.launch({ viewport, chromiumFlags, touch: false });
    await this.page.goto(this.url);
    return this;
  }

  async close() {
    await this.browser?.close();
    if (this.userDataDir) fs.rmSync(this.userDataDir, { recursive: true, force: true });
    await new Promise((resolve) => this.server?.close(resolve));
  }

  /** The status the page's backend gives it. */
  status() {
    return this.page.evaluate(() => backend.status());
  }

  /** Sends a command through the page's backend, as the page does. */
  async command(body) {
    const { status, answer } = await this.page.evaluate((command) => backend.command(command), body);
    return { status, body: answer };
  }
}
