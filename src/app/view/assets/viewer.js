// The page of `masssprings view`: draws, with plain WebGL, the simulation
// that runs in the masssprings process, and sends it keys and drags. It
// asks the simulation for everything through `backend` (backend.js), and
// draws its plot with plot.js.
//
// Each tab keeps its own camera; every command acts on the one simulation
// the server runs, so two tabs see the same cloth.
//
// Drawing, back to front: a background gradient, the mesh (textured or
// flat, lit on both sides), then, when shown (key L), the springs as lines
// and the point masses as discs sized to the mesh spacing, and always the
// pinned vertices as silver discs. When comparing, the second simulation
// beside the first (the same drawing, moved to its right) or as an orange
// wireframe over it, each with a label naming its solver.
//
// In front of a class: the keys work whatever control has focus (but a
// text field), Esc stops whatever runs, every number says what it is on
// hover, large print (Aa) is on by default on a window at most 1100 px
// wide, and on a phone the panels fold into a drawer.
'use strict';
// ---------------------------------------------------------------------------
// The look: the same numbers as `masssprings render` (src/app/render/look.rs),
// so a rendered GIF looks like this page.

function hex(rgb) {
  return [(rgb >> 16) & 255, (rgb >> 8) & 255, rgb & 255].map((c) => c / 255);
}

const LOOK = {
  backgroundTop: hex(0xf4f6f8),
  backgroundBottom: hex(0xdde3ea),
  cloth: hex(0x5b8fd6), // the mesh's colour without texture
  towardLight: normalize([-0.4, 0.8, 0.45]), // world space, upper left front
  ambient: 0.35,
  diffuse: 0.65, // brightness = ambient + diffuse · |n·l| (a thin sheet: both sides lit)
  spring: hex(0x33414f),
  springOpacity: 0.5,
  mass: hex(0xc0392b),
  massRadius: 2, // CSS pixels, when the scene gives no mass radius
  massRadiusLimits: [1, 6], // CSS pixels: dots sized to the mesh stay within
  pin: hex(0xc8ccd0),
  pinOutline: hex(0x7f8c8d),
  pinRadius: 3,
  pinOutlineWidth: 1,
  azimuthDegrees: 30, // camera direction: from +z toward +x…
  elevationDegrees: 20, // …and above the horizontal plane
  fieldOfViewDegrees: 35, // vertical
  margin: 1.1, // the scene fills at most 1/1.1 of the view
  second: hex(0xd35400), // the compared simulation's wireframe and plot
  secondOpacity: 0.8,
};

/** Pixels within which a shift-click picks the nearest vertex. */
const PICK_RADIUS = 24;
/** A touch held this long without moving pulls the nearest vertex. */
const LONG_PRESS_MS = 500;
/** Milliseconds between two status polls. */
const STATUS_PERIOD = 250;
/** A window at most this wide starts in large print (a projector, a phone). */
const LARGE_PRINT_WIDTH = 1100;
/** A window narrower than this is laid out as a phone's: the statistics
 *  and the controls side by side would overlap (in small and in large
 *  print). */
const NARROW_WIDTH = { small: 710, large: 780 };
/** Cloths whose box moved less than this share of its size over the
 *  last SETTLED_FRAMES frames have settled: the camera frames them again
 *  as they are. */
const SETTLED_MOTION = 0.01;
const SETTLED_FRAMES = 10;
const SETTLED_SHRINK = 0.8;
// ---------------------------------------------------------------------------
// Small vector and matrix helpers. Matrices are 4×4, column-major
// Float32Arrays, as WebGL's uniformMatrix4fv expects: m[4 * column + row].

function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function scale(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function cross(a, b) {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}
function normalize(a) {
  const length = Math.hypot(a[0], a[1], a[2]);
  return length > 0 ? scale(a, 1 / length) : [0, 0, 1];
}

/** The product a·b of two column-major 4×4 matrices. */
function multiply(a, b) {
  const out = new Float32Array(16);
  for (let column = 0; column < 4; column++) {
    for (let row = 0; row < 4; row++) {
      let sum = 0;
      for (let k = 0; k < 4; k++) sum += a[4 * k + row] * b[4 * column + k];
      out[4 * column + row] = sum;
    }
  }
  return out;
}

/** Perspective projection: camera space (looking down −z) → clip space,
 *  the centre of view moved by `shift` (in normalised device coordinates,
 *  right and up: a shifted lens, so that the scene sits in the free part
 *  of the window without turning the camera). */
function perspective(fovY, aspect, near, far, shift = [0, 0]) {
  const f = 1 / Math.tan(fovY / 2);
  const depth = 1 / (near - far);
  return new Float32Array([
    f / aspect, 0, 0, 0,
    0, f, 0, 0,
    -shift[0], -shift[1], (far + near) * depth, -1,
    0, 0, 2 * far * near * depth, 0,
  ]);
}

/** Translation by `offset`, as a 4×4 matrix. */
function translation(offset) {
  return new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, offset[0], offset[1], offset[2], 1]);
}

/** View matrix: world → camera space, for a camera at `eye` with the
 *  orthonormal axes right, up and back (it looks along −back). */
function viewMatrix(eye, right, up, back) {
  return new Float32Array([
    right[0], up[0], back[0], 0,
    right[1], up[1], back[1], 0,
    right[2], up[2], back[2], 0,
    -dot(right, eye), -dot(up, eye), -dot(back, eye), 1,
  ]);
}

/** Clip coordinates [x, y, z, w] of world point p under matrix m. */
function transform(m, p) {
  const out = [0, 0, 0, 0];
  for (let row = 0; row < 4; row++) {
    out[row] = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
  }
  return out;
}

// ---------------------------------------------------------------------------
// The orbit camera. It looks at `target` from the direction
//   back = (cos e · sin a, sin e, cos e · cos a)
// (azimuth a from +z toward +x, elevation e), from `distance` away; world y
// is up. A scene first faces the page at the azimuth the server chose
// (facing.rs: the face of the cloth as it will hang, not its edge).
//
// Framing fills the free part of the window: the largest rectangles no
// panel covers; the lens is shifted (`shift`, in normalised device
// coordinates) so that the scene's centre lands in the middle of the one
// the scene fits best, and the distance is the least at which the scene
// fits its width and height with the margin.
//
// The camera follows the cloth until the user moves it (orbit, pan, zoom);
// F frames the cloth as it is and follows it again. Following, it frames
// everything the cloths have occupied since it last framed them (a cloth
// never leaves the view), and frames them afresh, as they are, when a
// comparison starts or stops, when the drawing of the compared one
// changes, and when the cloths settle (their box all but still over
// SETTLED_FRAMES frames): a fallen flag then fills the height of the free
// area instead of the box of its fall.

const camera = {
  azimuth: LOOK.azimuthDegrees * Math.PI / 180,
  elevation: LOOK.elevationDegrees * Math.PI / 180,
  fovY: LOOK.fieldOfViewDegrees * Math.PI / 180,
  target: [0, 0, 0],
  distance: 1,
  shift: [0, 0],
  follow: true,
  box: emptyBox(),
  /** The cloths' boxes over the last frames, and whether the camera has
   *  framed them since they settled. */
  recent: [],
  framedStill: false,
};

function emptyBox() {
  return { min: [Infinity, Infinity, Infinity], max: [-Infinity, -Infinity, -Infinity] };
}

/** The camera's axes and eye for the current angles. */
function cameraFrame() {
  const cosE = Math.cos(camera.elevation);
  const back = [cosE * Math.sin(camera.azimuth), Math.sin(camera.elevation),
    cosE * Math.cos(camera.azimuth)];
  const right = normalize(cross([0, 1, 0], back));
  const up = cross(back, right);
  const eye = add(camera.target, scale(back, camera.distance));
  return { eye, right, up, back };
}

/** Grows the camera's box by `positions`, moved by `offset`. The box is
 *  in the camera's axes (right, up, back), so that it holds the cloths as
 *  tightly as the camera sees them (the orientation does not change while
 *  the camera follows). */
function growBox(positions, offset = [0, 0, 0]) {
  const { min, max } = camera.box;
  const axes = ['right', 'up', 'back'].map((name) => cameraFrame()[name]);
  for (let i = 0; i < positions.length; i += 3) {
    const p = [positions[i] + offset[0], positions[i + 1] + offset[1], positions[i + 2] + offset[2]];
    for (let k = 0; k < 3; k++) {
      const along = dot(p, axes[k]);
      min[k] = Math.min(min[k], along);
      max[k] = Math.max(max[k], along);
    }
  }
}

/** Grows the box by every simulation shown, where it is drawn. */
function growBoxByShown() {
  if (state.positions) growBox(state.positions);
  if (state.second) growBox(state.second, secondOffset());
}

/** The panels on the page, as shown (hidden ones left out): what framing
 *  keeps clear of. */
function panelRectangles() {
  return ['overlay', 'controls', 'help']
    .map((id) => document.getElementById(id).getBoundingClientRect())
    .filter((r) => r.width > 0 && r.height > 0);
}

/** The largest rectangles of the canvas (CSS pixels) that no panel covers,
 *  each { left, top, width, height }: every rectangle bounded by the
 *  canvas's and the panels' edges that meets no panel and is not inside
 *  another; the whole canvas when none is left. Comparing, the top of
 *  each is kept for the labels over the cloths. */
function freeAreas() {
  const width = canvas.clientWidth;
  const height = canvas.clientHeight;
  const gap = 8;
  const panels = panelRectangles();
  const lefts = [0, ...panels.map((r) => r.right + gap)];
  const rights = [width, ...panels.map((r) => r.left - gap)];
  const tops = [0, ...panels.map((r) => r.bottom + gap)];
  const bottoms = [height, ...panels.map((r) => r.top - gap)];
  const meets = (a, r) => a.left < r.right && a.right > r.left && a.top < r.bottom && a.bottom > r.top;
  const found = [];
  for (const left of lefts) for (const right of rights) for (const top of tops) for (const bottom of bottoms) {
    const a = { left, right, top, bottom };
    if (right - left < 80 || bottom - top < 80 || panels.some((r) => meets(a, r))) continue;
    if (!found.some((b) => b.left === left && b.right === right && b.top === top && b.bottom === bottom)) found.push(a);
  }
  const inside = (a, b) => a !== b && a.left >= b.left && a.right <= b.right && a.top >= b.top && a.bottom <= b.bottom;
  const largest = found.filter((a) => !found.some((b) => inside(a, b)));
  const labels = state.second ? 1.9 * labelFont() : 0;
  const areas = largest.map((a) => ({ left: a.left, top: a.top + labels, width: a.right - a.left,
    height: a.bottom - a.top - labels }));
  return areas.length > 0 ? areas : [{ left: 0, top: 0, width, height }];
}

/** The distance at which the box fits `area` (a rectangle of the canvas)
 *  with the margin, for the current angles (as src/app/render/camera.rs
 *  frames the whole image). */
function distanceToFit(area, aspect) {
  const { min, max } = camera.box;
  const tanY = Math.tan(camera.fovY / 2) * area.height / Math.max(1, canvas.clientHeight);
  const tanX = Math.tan(camera.fovY / 2) * aspect * area.width / Math.max(1, canvas.clientWidth);
  let distance = 1e-6;
  for (let corner = 0; corner < 8; corner++) {
    // The corner from the box's centre, along right, up and back.
    const o = [0, 1, 2].map((k) => ((corner >> k) & 1 ? max[k] - min[k] : min[k] - max[k]) / 2);
    const fit = Math.max(Math.abs(o[0]) / tanX, Math.abs(o[1]) / tanY);
    distance = Math.max(distance, o[2] + LOOK.margin * fit);
  }
  return distance;
}

/** Aims at the box: target = its centre, in the middle of the free area
 *  where it is largest (of the areas where it is within 10% of that, the
 *  largest area), at the least distance at which it fits there. */
function aimAtBox(aspect) {
  const { min, max } = camera.box;
  if (!(min[0] <= max[0])) return;
  const { right, up, back } = cameraFrame();
  const centre = scale(add(min, max), 0.5);
  const target = add(add(scale(right, centre[0]), scale(up, centre[1])), scale(back, centre[2]));
  const fits = freeAreas().map((area) => ({ area, distance: distanceToFit(area, aspect) }));
  const closest = Math.min(...fits.map((fit) => fit.distance));
  const size = ({ area }) => area.width * area.height;
  const { area, distance } = fits.filter((fit) => fit.distance <= 1.1 * closest)
    .reduce((best, fit) => (size(fit) > size(best) ? fit : best));
  camera.target = target;
  camera.distance = distance;
  camera.shift = [
    2 * (area.left + area.width / 2) / Math.max(1, canvas.clientWidth) - 1,
    1 - 2 * (area.top + area.height / 2) / Math.max(1, canvas.clientHeight),
  ];
  window.viewer.framedArea = area;
}

/** While following, frames everything seen since the last framing. */
function frameScene(aspect) {
  if (!camera.follow) return;
  growBoxByShown();
  aimAtBox(aspect);
}

/** Frames the cloths as they are now (while following). */
function frameAfresh() {
  if (!camera.follow || !state.positions) return;
  camera.box = emptyBox();
  growBoxByShown();
  aimAtBox(aspectRatio());
  window.viewer.refits++;
}

/** Key F: frames the cloth as it is now, and follows it again. */
function fitToCloth() {
  if (!state.positions) return;
  camera.follow = true;
  frameAfresh();
  window.viewer.fits++;
}

/** A new frame arrived: frames the cloths afresh once their box has kept
 *  still over the last SETTLED_FRAMES frames, when it has shrunk to less
 *  than SETTLED_SHRINK of the framed box across or up the screen (a
 *  fallen cloth; a flag flapping in the wind within the box framed keeps
 *  its camera). */
function watchSettling() {
  const saved = camera.box;
  camera.box = emptyBox();
  growBoxByShown();
  const box = camera.box;
  camera.box = saved;
  const recent = camera.recent;
  recent.push(box);
  if (recent.length > SETTLED_FRAMES) recent.shift();
  if (recent.length < SETTLED_FRAMES) return;
  const size = Math.hypot(...sub(box.max, box.min));
  const then = recent[0];
  const moved = Math.max(...[0, 1, 2].flatMap((k) => [Math.abs(box.min[k] - then.min[k]),
    Math.abs(box.max[k] - then.max[k])]));
  if (moved >= SETTLED_MOTION * size) {
    camera.framedStill = false;
  } else if (!camera.framedStill) {
    camera.framedStill = true;
    const extent = (b, k) => b.max[k] - b.min[k];
    const shrunk = [0, 1].some((k) => extent(box, k) < SETTLED_SHRINK * extent(saved, k));
    if (shrunk) frameAfresh();
  }
}

/** The user moved the camera: it stops following the cloth. */
function takeCamera() {
  camera.follow = false;
}

/** Moves the target by (dx, dy) CSS pixels across the screen. */
function pan(dx, dy) {
  const { right, up } = cameraFrame();
  const worldPerPixel = 2 * camera.distance * Math.tan(camera.fovY / 2) / Math.max(1, canvas.clientHeight);
  camera.target = add(camera.target, add(scale(right, -dx * worldPerPixel), scale(up, dy * worldPerPixel)));
  takeCamera();
}

/** Zooms by `factor` (< 1: closer) toward the point under (x, y): eye and
 *  target both move toward it, so that point stays under the cursor. */
function zoomToward(x, y, factor) {
  const matrices = cameraMatrices(aspectRatio());
  const anchor = pointUnderCursor(x, y, camera.target, matrices);
  camera.target = add(anchor, scale(sub(camera.target, anchor), factor));
  camera.distance *= factor;
  takeCamera();
}

/** projection · view, and the pieces picking needs. */
function cameraMatrices(aspect) {
  const frame = cameraFrame();
  const near = camera.distance / 100;
  const far = camera.distance * 100;
  const view = viewMatrix(frame.eye, frame.right, frame.up, frame.back);
  const projection = perspective(camera.fovY, aspect, near, far, camera.shift);
  const viewProjection = multiply(projection, view);
  return { ...frame, viewProjection, aspect };
}

// ---------------------------------------------------------------------------
// Shaders (GLSL ES 1.00: they run in WebGL 1 and 2).

const SHADERS = {
  // A full-screen triangle coloured from bottom to top.
  background: {
    vertex: `
      attribute vec2 a_corner;
      varying float v_height;
      void main() {
        v_height = 0.5 * (a_corner.y + 1.0);
        gl_Position = vec4(a_corner, 0.0, 1.0);
      }`,
    fragment: `
      precision mediump float;
      uniform vec3 u_top, u_bottom;
      varying float v_height;
      void main() { gl_FragColor = vec4(mix(u_bottom, u_top, v_height), 1.0); }`,
  },
  // The mesh: two-sided Lambert lighting of a texture or a flat colour.
  mesh: {
    vertex: `
      attribute vec3 a_position, a_normal;
      attribute vec2 a_uv;
      uniform mat4 u_viewProjection;
      varying vec3 v_normal;
      varying vec2 v_uv;
      void main() {
        v_normal = a_normal;
        v_uv = a_uv;
        gl_Position = u_viewProjection * vec4(a_position, 1.0);
      }`,
    fragment: `
      precision mediump float;
      uniform vec3 u_towardLight, u_cloth;
      uniform float u_ambient, u_diffuse;
      uniform bool u_textured;
      uniform sampler2D u_texture;
      varying vec3 v_normal;
      varying vec2 v_uv;
      void main() {
        // Cloth has no inside: light the side we see (flip the back's normal).
        vec3 n = normalize(v_normal);
        if (!gl_FrontFacing) n = -n;
        // A thin sheet: the light reaches the side we see through it too.
        float brightness = u_ambient + u_diffuse * abs(dot(n, u_towardLight));
        vec3 colour = u_textured ? texture2D(u_texture, v_uv).rgb : u_cloth;
        gl_FragColor = vec4(colour * brightness, 1.0);
      }`,
  },
  // Springs: lines of one colour and opacity.
  lines: {
    vertex: `
      attribute vec3 a_position;
      uniform mat4 u_viewProjection;
      void main() { gl_Position = u_viewProjection * vec4(a_position, 1.0); }`,
    fragment: `
      precision mediump float;
      uniform vec4 u_colour;
      void main() { gl_FragColor = u_colour; }`,
  },
  // Point masses: round discs with an optional outline, of a fixed radius
  // in pixels, or (u_worldRadius > 0) of a radius in world units, clamped.
  points: {
    vertex: `
      attribute vec3 a_position;
      uniform mat4 u_viewProjection;
      uniform float u_radius, u_worldRadius, u_pixelsPerUnit, u_minRadius, u_maxRadius;
      varying float v_radius;
      void main() {
        gl_Position = u_viewProjection * vec4(a_position, 1.0);
        v_radius = u_worldRadius > 0.0
          ? clamp(u_worldRadius * u_pixelsPerUnit / gl_Position.w, u_minRadius, u_maxRadius)
          : u_radius;
        gl_PointSize = 2.0 * v_radius + 1.0;
      }`,
    fragment: `
      precision mediump float;
      uniform vec3 u_fill, u_outline;
      uniform float u_outlineWidth;
      varying float v_radius;
      void main() {
        float d = length(gl_PointCoord - 0.5) * (2.0 * v_radius + 1.0); // pixels from the centre
        if (d > v_radius) discard;
        gl_FragColor = vec4(d > v_radius - u_outlineWidth ? u_outline : u_fill, 1.0);
      }`,
  },
};

function compileProgram(gl, source) {
  const program = gl.createProgram();
  for (const [type, text] of [[gl.VERTEX_SHADER, source.vertex], [gl.FRAGMENT_SHADER, source.fragment]]) {
    const shader = gl.createShader(type);
    gl.shaderSource(shader, text);
    gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
      throw new Error(gl.getShaderInfoLog(shader));
    }
    gl.attachShader(program, shader);
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  // Look every attribute and uniform up once, by name.
  const locations = {};
  for (let i = 0; i < gl.getProgramParameter(program, gl.ACTIVE_ATTRIBUTES); i++) {
    const name = gl.getActiveAttrib(program, i).name;
    locations[name] = gl.getAttribLocation(program, name);
  }
  for (let i = 0; i < gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS); i++) {
    const name = gl.getActiveUniform(program, i).name;
    locations[name] = gl.getUniformLocation(program, name);
  }
  return { program, locations };
}

// ---------------------------------------------------------------------------
// The scene on the GPU. Two sets of vertices:
// * simulated vertices (n, in the server's order): springs and points;
// * display vertices, one per distinct (vertex, texture coordinate) pair
//   (see src/app/view/display_mesh.rs): the triangles. Each frame copies
//   each display vertex's position and normal from its simulated vertex.
// The positions and normals are kept per simulation shown (`gpu.sets`: the
// first, and the second when comparing); the indices are shared.
//
// Without WebGL (`fallback`), nothing of this is made: the page shows the
// images the server draws (below, "Without WebGL").

const canvas = document.getElementById('view');
const overlay = document.getElementById('overlay');
const statsText = document.getElementById('stats');
const gl = new URLSearchParams(location.search).has('images') ? null
  : canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true })
  || canvas.getContext('webgl', { antialias: true, preserveDrawingBuffer: true });
const fallback = !gl;

const state = {
  scene: null, // /api/scene
  status: null, // the latest /api/status
  positions: null, // Float32Array(3n): the latest frame
  second: null, // Float32Array(3n): the compared simulation's, when comparing
  serial: null, // the latest frame's serial
  frameSteps: null, // and its step count
  connected: true,
  frameRequestPending: false,
  statusRequestPending: false,
  dragged: null, // { vertex, point, offset } while shift-dragging
  dragTarget: null, // where the dragged vertex is pulled to
  sceneSerial: null, // status.scene_serial of the scene drawn
  loadingScene: false,
  refusal: null, // why the last command was refused
  waiting: null, // a command that waits for the step in progress
  sliderHeld: false,
  pending: new Set(), // controls whose command is not answered yet
  layout: 'beside', // how the compared simulation is drawn: beside, overlay
};

// What tests (tests/browser) read.
window.viewer = {
  ready: false, framesReceived: 0, framesDrawn: 0, textureLoaded: false, error: null,
  fits: 0, refits: 0, scenesLoaded: 0, plotPoints: 0, plotText: [], fallback, imagesDrawn: 0, framedArea: null,
  lastCommand: null, // { command, status, ms } of the last command answered
  state, camera, look: LOOK,
  screenPositionOf: (vertex, set = 0) => screenPosition(vertex, cameraMatrices(aspectRatio()), set),
  freeAreas: () => freeAreas(),
  panels: () => panelRectangles().map((r) => r.toJSON()),
};

let gpu = null; // programs and buffers, made once the scene is known

function createGpuScene(scene) {
  const isWebGL2 = typeof WebGL2RenderingContext !== 'undefined' && gl instanceof WebGL2RenderingContext;
  if (!isWebGL2 && !gl.getExtension('OES_element_index_uint')) {
    throw new Error('this browser cannot index more than 65,536 vertices');
  }
  const pinned = new Uint8Array(scene.n);
  for (const i of scene.pinned) pinned[i] = 1;
  const freeVertices = [];
  for (let i = 0; i < scene.n; i++) if (!pinned[i]) freeVertices.push(i);
  const displayCount = scene.display_vertices.length;
  return {
    isWebGL2,
    programs: Object.fromEntries(Object.entries(SHADERS).map(([name, source]) => [name, compileProgram(gl, source)])),
    backgroundCorners: buffer(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW),
    springs: buffer(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(scene.springs), gl.STATIC_DRAW),
    springIndexCount: scene.springs.length,
    freeVertices: buffer(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(freeVertices), gl.STATIC_DRAW),
    freeVertexCount: freeVertices.length,
    pins: buffer(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(scene.pinned), gl.STATIC_DRAW),
    pinCount: scene.pinned.length,
    pinned,
    meshUvs: buffer(gl.ARRAY_BUFFER, new Float32Array(scene.texture_coords.length
      ? scene.texture_coords : 2 * displayCount), gl.STATIC_DRAW),
    triangles: buffer(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(scene.triangles), gl.STATIC_DRAW),
    triangleIndexCount: scene.triangles.length,
    // One position of the drag marker: the dragged vertex and its target.
    dragLine: buffer(gl.ARRAY_BUFFER, new Float32Array(6), gl.DYNAMIC_DRAW),
    texture: null,
    sets: [setBuffers(scene)],
  };
}

function buffer(target, data, usage) {
  const b = gl.createBuffer();
  gl.bindBuffer(target, b);
  gl.bufferData(target, data, usage);
  return b;
}

/** The buffers of one simulation's positions and normals. */
function setBuffers(scene) {
  const displayCount = scene.display_vertices.length;
  return {
    positions: buffer(gl.ARRAY_BUFFER, new Float32Array(3 * scene.n), gl.DYNAMIC_DRAW),
    displayPositions: new Float32Array(3 * displayCount),
    displayNormals: new Float32Array(3 * displayCount),
    vertexNormals: new Float32Array(3 * scene.n),
    meshPositions: buffer(gl.ARRAY_BUFFER, new Float32Array(3 * displayCount), gl.DYNAMIC_DRAW),
    meshNormals: buffer(gl.ARRAY_BUFFER, new Float32Array(3 * displayCount), gl.DYNAMIC_DRAW),
  };
}

/** The pinned vertices, for picking (with or without WebGL). */
function pinnedVertices() {
  if (gpu) return gpu.pinned;
  if (!state.pinnedVertices) {
    state.pinnedVertices = new Uint8Array(state.scene.n);
    for (const i of state.scene.pinned) state.pinnedVertices[i] = 1;
  }
  return state.pinnedVertices;
}

/** Loads the scene's PNG; the mesh stays flat-coloured until it arrives. */
function loadTexture(url) {
  const image = new Image();
  image.onload = () => {
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, texture);
    // OBJ texture coordinates have v = 0 at the bottom; images start at the top.
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, true);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB, gl.RGB, gl.UNSIGNED_BYTE, image);
    const powerOfTwo = (x) => (x & (x - 1)) === 0;
    // WebGL 1 can repeat only power-of-two textures; WebGL 2 any.
    const wrap = gpu.isWebGL2 || (powerOfTwo(image.width) && powerOfTwo(image.height))
      ? gl.REPEAT : gl.CLAMP_TO_EDGE;
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, wrap);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, wrap);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gpu.texture = texture;
    window.viewer.textureLoaded = true;
  };
  image.onerror = () => {
    // a PNG the server decodes is never served broken; a user's own, read
    // by the page, can be
    state.refusal = 'texture: the browser cannot decode this PNG; the cloth is drawn without it';
    window.viewer.textureLoaded = true;
  };
  image.src = url;
}

/** Takes a new frame of simulation `index` (0, or 1 when comparing):
 *  positions, smooth normals, and the display copies. */
function applyFrame(positions, index) {
  if (index === 0) state.positions = positions; else state.second = positions;
  if (!gpu) return; // without WebGL the server draws
  if (!gpu.sets[index]) gpu.sets[index] = setBuffers(state.scene);
  const set = gpu.sets[index];
  vertexNormals(positions, set.vertexNormals);
  // Display vertex d shows simulated vertex vertexOf[d].
  const vertexOf = state.scene.display_vertices;
  const normals = set.vertexNormals;
  for (let d = 0; d < vertexOf.length; d++) {
    const v = 3 * vertexOf[d];
    const n = normalize([normals[v], normals[v + 1], normals[v + 2]]);
    for (let k = 0; k < 3; k++) {
      set.displayPositions[3 * d + k] = positions[v + k];
      set.displayNormals[3 * d + k] = n[k];
    }
  }
  gl.bindBuffer(gl.ARRAY_BUFFER, set.positions);
  gl.bufferSubData(gl.ARRAY_BUFFER, 0, positions);
  gl.bindBuffer(gl.ARRAY_BUFFER, set.meshPositions);
  gl.bufferSubData(gl.ARRAY_BUFFER, 0, set.displayPositions);
  gl.bindBuffer(gl.ARRAY_BUFFER, set.meshNormals);
  gl.bufferSubData(gl.ARRAY_BUFFER, 0, set.displayNormals);
}

/** Vertex normals: the sum of the unnormalised normals (b − a) × (c − a)
 *  of the triangles around each vertex (larger triangles weigh more). */
function vertexNormals(positions, normals) {
  normals.fill(0);
  const tri = state.scene.triangles;
  const vertexOf = state.scene.display_vertices;
  for (let t = 0; t < tri.length; t += 3) {
    const a = 3 * vertexOf[tri[t]], b = 3 * vertexOf[tri[t + 1]], c = 3 * vertexOf[tri[t + 2]];
    const ab = [positions[b] - positions[a], positions[b + 1] - positions[a + 1], positions[b + 2] - positions[a + 2]];
    const ac = [positions[c] - positions[a], positions[c + 1] - positions[a + 1], positions[c + 2] - positions[a + 2]];
    const n = cross(ab, ac);
    for (const v of [a, b, c]) {
      normals[v] += n[0]; normals[v + 1] += n[1]; normals[v + 2] += n[2];
    }
  }
}

/** Where the compared simulation is drawn, relative to the first: beside
/** Where the compared simulation is drawn, relative to the first: beside
 *  it, to its right for the scene's first view (the server's `beside`:
 *  a fifth more than the rest shape's width that way), or over it. */
function secondOffset() {
  if (state.layout !== 'beside' || !state.scene) return [0, 0, 0];
  return state.scene.beside;
}

// ---------------------------------------------------------------------------
// Drawing.

function aspectRatio() {
  return canvas.clientWidth / Math.max(1, canvas.clientHeight);
}

/** Matches the drawing buffer to the canvas's size on screen. */
function resizeCanvas() {
  const ratio = window.devicePixelRatio || 1;
  const width = Math.round(canvas.clientWidth * ratio);
  const height = Math.round(canvas.clientHeight * ratio);
  if (canvas.width !== width || canvas.height !== height) {
    canvas.width = width;
    canvas.height = height;
  }
  if (gl) gl.viewport(0, 0, width, height);
  return ratio;
}

function bindAttribute(location, buffer, size) {
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.enableVertexAttribArray(location);
  gl.vertexAttribPointer(location, size, gl.FLOAT, false, 0, 0);
}

function draw() {
  const pixelRatio = resizeCanvas();
  const aspect = aspectRatio();
  if (state.positions) frameScene(aspect);
  const matrices = cameraMatrices(aspect);
  drawBackground();
  if (!state.positions) return;
  gl.enable(gl.DEPTH_TEST);
  gl.depthFunc(gl.LEQUAL);
  drawSimulation(matrices, gpu.sets[0], pixelRatio);
  if (state.second && gpu.sets[1]) {
    if (state.layout === 'beside') {
      const moved = { ...matrices, viewProjection: multiply(matrices.viewProjection, translation(secondOffset())) };
      drawSimulation(moved, gpu.sets[1], pixelRatio);
    } else {
      drawWireframe(matrices, gpu.sets[1]);
    }
  }
  if (state.dragged && state.dragTarget) drawDragMarker(matrices, pixelRatio);
  placeLabels(matrices);
  window.viewer.framesDrawn++;
}

/** One simulation: its mesh, its springs and masses when shown (key L),
 *  and its pins (always, in silver). */
function drawSimulation(matrices, set, pixelRatio) {
  drawMesh(matrices, set);
  if (state.status && state.status.show_springs) {
    drawLines(matrices, set, [...LOOK.spring, LOOK.springOpacity]);
    drawPoints(matrices, set, gpu.freeVertices, gpu.freeVertexCount, LOOK.mass, LOOK.mass, LOOK.massRadius, 0,
      pixelRatio, state.scene.mass_radius || 0);
  }
  drawPoints(matrices, set, gpu.pins, gpu.pinCount, LOOK.pin, LOOK.pinOutline, LOOK.pinRadius,
    LOOK.pinOutlineWidth, pixelRatio);
}

/** The compared simulation over the first: its springs as orange lines,
 *  in front of everything. */
function drawWireframe(matrices, set) {
  gl.disable(gl.DEPTH_TEST);
  drawLines(matrices, set, [...LOOK.second, LOOK.secondOpacity]);
  gl.enable(gl.DEPTH_TEST);
}

function drawBackground() {
  const { program, locations } = gpu.programs.background;
  gl.disable(gl.DEPTH_TEST);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  gl.useProgram(program);
  gl.uniform3fv(locations.u_top, LOOK.backgroundTop);
  gl.uniform3fv(locations.u_bottom, LOOK.backgroundBottom);
  bindAttribute(locations.a_corner, gpu.backgroundCorners, 2);
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  gl.disableVertexAttribArray(locations.a_corner);
}

function drawMesh(matrices, set) {
  if (gpu.triangleIndexCount === 0) return; // a scene of springs only
  const { program, locations } = gpu.programs.mesh;
  gl.useProgram(program);
  gl.uniformMatrix4fv(locations.u_viewProjection, false, matrices.viewProjection);
  gl.uniform3fv(locations.u_towardLight, LOOK.towardLight);
  gl.uniform3fv(locations.u_cloth, LOOK.cloth);
  gl.uniform1f(locations.u_ambient, LOOK.ambient);
  gl.uniform1f(locations.u_diffuse, LOOK.diffuse);
  gl.uniform1i(locations.u_textured, gpu.texture ? 1 : 0);
  if (gpu.texture) {
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, gpu.texture);
    gl.uniform1i(locations.u_texture, 0);
  }
  bindAttribute(locations.a_position, set.meshPositions, 3);
  bindAttribute(locations.a_normal, set.meshNormals, 3);
  bindAttribute(locations.a_uv, gpu.meshUvs, 2);
  // Push the surface slightly back so springs and points on it win the
  // depth test.
  gl.enable(gl.POLYGON_OFFSET_FILL);
  gl.polygonOffset(1, 1);
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, gpu.triangles);
  gl.drawElements(gl.TRIANGLES, gpu.triangleIndexCount, gl.UNSIGNED_INT, 0);
  gl.disable(gl.POLYGON_OFFSET_FILL);
  for (const name of ['a_position', 'a_normal', 'a_uv']) gl.disableVertexAttribArray(locations[name]);
}

/** The springs of `set` as lines of `colour` (RGBA). */
function drawLines(matrices, set, colour) {
  const { program, locations } = gpu.programs.lines;
  gl.useProgram(program);
  gl.uniformMatrix4fv(locations.u_viewProjection, false, matrices.viewProjection);
  gl.uniform4fv(locations.u_colour, colour);
  bindAttribute(locations.a_position, set.positions, 3);
  gl.enable(gl.BLEND);
  gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
  gl.depthMask(false); // translucent lines must not hide each other
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, gpu.springs);
  gl.drawElements(gl.LINES, gpu.springIndexCount, gl.UNSIGNED_INT, 0);
  gl.depthMask(true);
  gl.disable(gl.BLEND);
  gl.disableVertexAttribArray(locations.a_position);
}

/** Discs at the simulated vertices of `set` listed in `indexBuffer`. */
function drawPoints(matrices, set, indexBuffer, count, fill, outline, radius, outlineWidth, pixelRatio,
  worldRadius = 0) {
  if (count === 0) return;
  const { program, locations } = gpu.programs.points;
  gl.useProgram(program);
  gl.uniformMatrix4fv(locations.u_viewProjection, false, matrices.viewProjection);
  setPointRadius(locations, radius * pixelRatio, worldRadius, pixelRatio);
  gl.uniform1f(locations.u_outlineWidth, outlineWidth * pixelRatio);
  gl.uniform3fv(locations.u_fill, fill);
  gl.uniform3fv(locations.u_outline, outline);
  bindAttribute(locations.a_position, set.positions, 3);
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indexBuffer);
  gl.drawElements(gl.POINTS, count, gl.UNSIGNED_INT, 0);
  gl.disableVertexAttribArray(locations.a_position);
}

/** The points program's radius: `pixels` (device pixels), or, when
 *  `worldRadius` > 0, that many world units at each point's depth, kept
 *  within LOOK.massRadiusLimits. */
function setPointRadius(locations, pixels, worldRadius, pixelRatio) {
  const [least, most] = LOOK.massRadiusLimits;
  gl.uniform1f(locations.u_radius, pixels);
  gl.uniform1f(locations.u_worldRadius, worldRadius);
  // Device pixels per world unit at clip w = 1: f · height / 2.
  gl.uniform1f(locations.u_pixelsPerUnit, canvas.height / 2 / Math.tan(camera.fovY / 2));
  gl.uniform1f(locations.u_minRadius, least * pixelRatio);
  gl.uniform1f(locations.u_maxRadius, most * pixelRatio);
}

/** A line from the dragged vertex to where the mouse pulls it, and a disc
 *  at the target, drawn over everything. */
function drawDragMarker(matrices, pixelRatio) {
  const { from, to } = dragMarker();
  gl.bindBuffer(gl.ARRAY_BUFFER, gpu.dragLine);
  gl.bufferSubData(gl.ARRAY_BUFFER, 0, new Float32Array([...from, ...to]));
  gl.disable(gl.DEPTH_TEST);
  let { program, locations } = gpu.programs.lines;
  gl.useProgram(program);
  gl.uniformMatrix4fv(locations.u_viewProjection, false, matrices.viewProjection);
  gl.uniform4fv(locations.u_colour, [...LOOK.mass, 1]);
  bindAttribute(locations.a_position, gpu.dragLine, 3);
  gl.drawArrays(gl.LINES, 0, 2);
  ({ program, locations } = gpu.programs.points);
  gl.useProgram(program);
  gl.uniformMatrix4fv(locations.u_viewProjection, false, matrices.viewProjection);
  setPointRadius(locations, LOOK.pinRadius * pixelRatio, 0, pixelRatio);
  gl.uniform1f(locations.u_outlineWidth, LOOK.pinOutlineWidth * pixelRatio);
  gl.uniform3fv(locations.u_fill, LOOK.mass);
  gl.uniform3fv(locations.u_outline, LOOK.spring);
  bindAttribute(locations.a_position, gpu.dragLine, 3);
  gl.drawArrays(gl.POINTS, 1, 1);
  gl.disableVertexAttribArray(locations.a_position);
}

/** Where the drag marker runs, in world space as drawn: from the dragged
 *  vertex of the copy that was picked to where it is pulled. */
function dragMarker() {
  const { vertex, offset, set } = state.dragged;
  const positions = set === 1 && state.second ? state.second : state.positions;
  const from = add(Array.from(positions.subarray(3 * vertex, 3 * vertex + 3)), offset);
  return { from, to: add(state.dragTarget, offset) };
}

// ---------------------------------------------------------------------------
// Without WebGL: the server draws each frame with the crate's own renderer
// (src/app/render, as `masssprings render` does) for this page's camera,
// and the page shows the PNG on a 2D canvas, asking for the next one when
// the frame, the camera or the window changed and the last one arrived.
// Everything else (camera, picking, drags, keys, controls) is the same.

const imageView = { pending: false, key: null, context: null };

function drawImage() {
  resizeCanvas();
  if (state.positions) frameScene(aspectRatio());
  const key = imageKey();
  if (imageView.pending || key === imageView.key || !state.positions) return;
  imageView.pending = true;
  backend.image(key)
    .then((blob) => createImageBitmap(blob))
    .then((bitmap) => {
      imageView.context = imageView.context || canvas.getContext('2d');
      imageView.context.drawImage(bitmap, 0, 0, canvas.width, canvas.height);
      if (state.dragged && state.dragTarget) drawDragMarker2d(imageView.context);
      placeLabels(cameraMatrices(aspectRatio()));
      imageView.key = key;
      window.viewer.imagesDrawn++;
      window.viewer.framesDrawn++;
    })
    .catch((error) => {
      window.viewer.error = String(error);
      state.refusal = error.message;
    })
    .finally(() => { imageView.pending = false; });
}

/** The most pixels an image is asked for (the server draws at most 2
 *  million); a larger canvas shows it stretched. */
const IMAGE_PIXELS = 1.5e6;

/** The query of the image for the current frame and camera. */
function imageKey() {
  const shrink = Math.min(1, Math.sqrt(IMAGE_PIXELS / Math.max(1, canvas.width * canvas.height)));
  const parameters = {
    w: Math.max(16, Math.floor(canvas.width * shrink)), h: Math.max(16, Math.floor(canvas.height * shrink)),
    tx: camera.target[0], ty: camera.target[1], tz: camera.target[2],
    az: camera.azimuth, el: camera.elevation, d: camera.distance, fov: camera.fovY,
    sx: camera.shift[0], sy: camera.shift[1],
    springs: state.status && state.status.show_springs ? 1 : 0,
    ox: secondOffset()[0],
    oz: secondOffset()[2],
    frame: state.serial,
  };
  if (state.dragged && state.dragTarget) parameters.drag = state.dragTarget.join(',');
  return Object.entries(parameters).map(([name, value]) => `${name}=${value}`).join('&');
}

/** The drag marker over the image: a line and a disc, in CSS pixels. */
function drawDragMarker2d(context) {
  const matrices = cameraMatrices(aspectRatio());
  const { from, to } = dragMarker();
  const ratio = canvas.width / Math.max(1, canvas.clientWidth);
  const [a, b] = [from, to].map((p) => project(p, matrices));
  if (!a || !b) return;
  context.save();
  context.scale(ratio, ratio);
  context.strokeStyle = context.fillStyle = `rgb(${LOOK.mass.map((c) => 255 * c).join(',')})`;
  context.beginPath();
  context.moveTo(a.x, a.y);
  context.lineTo(b.x, b.y);
  context.stroke();
  context.beginPath();
  context.arc(b.x, b.y, LOOK.pinRadius, 0, 2 * Math.PI);
  context.fill();
  context.restore();
}

// ---------------------------------------------------------------------------
// Talking to the simulation, through `backend` (backend.js). A command is
// answered 200 (applied), 409 (refused: the reason is shown) or 202: it
// waits for the work in progress and is applied after it, answered at
// once when that work will not end soon (a refusal then shows in the
// status's note); the overlay says which, and ■ stop (Esc) stops the work.

async function sendCommand(body) {
  const started = performance.now();
  const { status, ok, waits, answer } = await backend.command(body);
  window.viewer.lastCommand = { command: body.command, status, ms: performance.now() - started };
  if (ok) {
    state.status = answer;
    state.refusal = null;
    // Waiting lasts until the work ends (onStatus), whatever another
    // command's answer says meanwhile.
    if (waits) state.waiting = body.command;
  } else {
    state.refusal = `${body.command}: ${answer.error}`;
    console.warn('command refused:', body.command, answer.error);
  }
  onStatus();
  return { status, answer };
}

/** Sends `body`; `control` (an id), if given, is not overwritten by the
 *  status until the answer has come. */
function send(body, control = null) {
  if (control) state.pending.add(control);
  return sendCommand(body)
    .catch(() => setConnected(false))
    .finally(() => { if (control) state.pending.delete(control); });
}

/** Asks for the frame after the one we have; null means nothing moved. */
async function pollFrame() {
  if (state.frameRequestPending || state.loadingScene) return;
  state.frameRequestPending = true;
  try {
    const bytes = await backend.frame(state.serial);
    if (bytes) takeFrame(bytes);
    setConnected(true);
  } catch (error) {
    setConnected(false);
    await new Promise((resolve) => setTimeout(resolve, 500));
  } finally {
    state.frameRequestPending = false;
  }
}

/** A frame (src/app/view/api.rs): u32 n, u32 serial, u32 steps, f32 time,
 *  then 3n floats per simulation shown. */
function takeFrame(bytes) {
  const header = new DataView(bytes, 0, 16);
  const n = header.getUint32(0, true);
  if (!state.scene || n !== state.scene.n || state.loadingScene) return;
  const sets = (bytes.byteLength - 16) / (12 * n);
  const comparedBefore = state.second !== null;
  state.serial = header.getUint32(4, true);
  state.frameSteps = header.getUint32(8, true);
  applyFrame(new Float32Array(bytes, 16, 3 * n), 0);
  if (sets === 2) applyFrame(new Float32Array(bytes, 16 + 12 * n, 3 * n), 1); else state.second = null;
  // A comparison started or stopped: frame what is shown now.
  if ((state.second !== null) !== comparedBefore) {
    camera.recent = [];
    frameAfresh();
  }
  watchSettling();
  window.viewer.framesReceived++;
}

async function pollStatus() {
  if (state.statusRequestPending) return; // a slow answer is not asked for again meanwhile
  state.statusRequestPending = true;
  try {
    state.status = await backend.status();
    setConnected(true);
  } catch (error) {
    setConnected(false);
  } finally {
    state.statusRequestPending = false;
  }
  onStatus();
}

function setConnected(connected) {
  state.connected = connected;
  overlay.classList.toggle('disconnected', !connected);
}

/** Fetches the scene the server shows (at start, and when it changes):
 *  the mesh, its texture, a fresh camera facing it. */
async function loadScene() {
  state.loadingScene = true;
  try {
    state.scene = await backend.scene();
    state.pinnedVertices = null;
    gpu = fallback ? null : createGpuScene(state.scene);
    window.viewer.textureLoaded = fallback;
    if (state.scene.texture && !fallback) loadTexture(backend.textureUrl(state.scene.texture, state.sceneSerial));
    state.positions = null;
    state.second = null;
    state.serial = null;
    camera.box = emptyBox();
    camera.recent = [];
    camera.follow = true;
    camera.azimuth = state.scene.azimuth;
    camera.elevation = LOOK.elevationDegrees * Math.PI / 180;
    window.viewer.scenesLoaded++;
  } finally {
    state.loadingScene = false;
  }
}

/** A new status: a changed scene is fetched; the overlay, the plot and the
 *  controls follow. */
function onStatus() {
  const s = state.status;
  if (s && state.sceneSerial !== null && s.scene_serial !== state.sceneSerial && !state.loadingScene) {
    state.sceneSerial = s.scene_serial;
    loadScene().catch((error) => { window.viewer.error = String(error); });
  }
  if (s && !s.busy) state.waiting = null;
  updateOverlay();
  updatePlot();
  syncControls();
}

// ---------------------------------------------------------------------------
// The statistics: one line each, every number with its unit and, on
// hover, what it is. On a phone with the drawer closed, only the lines
// that say where the simulation is and what it is doing.

/** The names of the solvers, as the page says them. */
const SOLVER_LABELS = {
  assignment: 'the assignment (plain, 50 iterations)',
  textbook: 'the handout\'s code',
  'accuracy-assignment': 'fast: every step as low in energy as the assignment\'s',
  converged: 'converged (L-BFGS, energy tolerance 1e-3)',
  frames: 'your frames',
};

/** Short names, for the labels over the cloths and the plot's legend. */
const SHORT_LABELS = {
  assignment: 'assignment (plain-50)',
  textbook: 'handout\'s code',
  'accuracy-assignment': 'fast (its energy)',
  converged: 'converged (L-BFGS)',
  frames: 'your frames',
};

/** How a simulation is solved, in words: its solver, or its method. */
function solvedBy(solver, backendName, method, labels = SOLVER_LABELS) {
  if (!solver) return `${method} (expert settings)`;
  return solver === 'textbook' ? `${labels.textbook}, ${backendName}` : labels[solver];
}

/** The two simulations' short names: the first, and the compared one. */
function simulationNames(s) {
  const first = solvedBy(s.solver, s.backend, s.method, SHORT_LABELS);
  const c = s.compare;
  return [first, c ? solvedBy(c.solver, c.backend, c.method, SHORT_LABELS) : ''];
}

/** What the fast mode keeps and what it does not. */
const FAST_MODE = 'keeps: every step ends at an energy no higher than the assignment\'s 50 plain iterations reach '
  + 'from the same state; does not keep: the assignment\'s animation: it leaves less of each step undone, so it '
  + 'damps less and the cloth falls sooner (docs/convergence.md, section 6)';

/** What the relative gradient says. */
const RELATIVE_GRADIENT = '‖∇E(p)‖ where the step stopped over ‖∇E(pᵗ)‖ where it started, on the free vertices (no '
  + 'unit; 1: no closer to the minimum by this measure). On cloth it follows the stiff modes, which the first '
  + 'iterations kill, not the slow ones where the energy left is: 50 plain iterations take much energy off and '
  + 'still leave it near 1 (docs/convergence.md, section 4)';

/** Why a step stopped: in a word or two, and in a sentence. */
const STOP_REASONS = {
  iterations: ['its budget', 'it ran every iteration it was allowed'],
  tolerance: ['tolerance', 'its relative gradient reached the tolerance'],
  'energy-tolerance': ['energy tolerance', 'an iteration took off at most the energy tolerance\'s share of what the '
    + 'step had taken off (the energy had stopped falling steeply)'],
  'at-least-plain': ['plain-50\'s decrease', 'its energy fell by at least what 50 plain iterations take off'],
  stalled: ['stalled', 'the line search found nothing lower: as good as rounding lets this method make it'],
};

/** A piece of a line: `text`, explained by `title` on hover. */
function piece(text, title) {
  return { text, title };
}

function updateOverlay() {
  const s = state.status;
  if (!state.connected) {
    statsText.textContent = 'disconnected: is masssprings view still running?';
    return;
  }
  if (!s) return;
  const lines = [...describeScene(s), ...describeWork(s), ...describeComparison(s)];
  statsText.replaceChildren(...lines.map(({ pieces, detail, fine, path }) => {
    const line = document.createElement('div');
    if (detail) line.classList.add('detail');
    if (fine) line.classList.add('fine');
    if (path) line.classList.add('path');
    line.append(...pieces.map((p) => {
      if (typeof p === 'string') return p;
      const span = document.createElement('span');
      span.textContent = p.text;
      span.title = p.title;
      return span;
    }));
    return line;
  }));
}

/** A line of the statistics; `detail`: folded away on a phone; `fine`:
 *  not in large print either; `path`: the functions that run (a fine
 *  detail in small type). */
function line(pieces, { detail = false, fine = false, path = false } = {}) {
  return { pieces, detail: detail || fine || path, fine, path };
}

/** The scene, the solve and its path, the parameters, the timings. */
function describeScene(s) {
  const tolerance = (s.tolerance === null ? 'all iterations' : `tolerance ${s.tolerance.toExponential(0)}`)
    + (s.energy_tolerance === null ? '' : ` · energy tolerance ${formatNumber(s.energy_tolerance)}`)
    + (s.at_least_plain === null ? '' : ` · at least plain-${s.at_least_plain}`);
  const solve = s.solver === 'accuracy-assignment'
    ? [piece(`solve: ${SOLVER_LABELS[s.solver]}, not its motion`, `${FAST_MODE}. Runs ${s.functions}`)]
    : [piece(`solve: ${solvedBy(s.solver, s.backend, s.method)}`, `runs ${s.functions}`)];
  return [
    line([`${s.scene} · `, piece(`${s.n.toLocaleString('en')} vertices`, 'n: the point masses (the OBJ\'s v lines)'),
      ' · ', piece(`${s.springs.toLocaleString('en')} springs`, 'the edges of the faces and their diagonals'),
      ' · ', piece(s.backend, 'the matrices Q is built and factored on: sparse (CSC) or dense')]),
    line(solve),
    line([`  ${s.functions}`], { detail: true, path: true }),
    line([piece(`k ${formatNumber(s.k)} N/m`, 'spring stiffness k'), ' · ',
      piece(`Δt ${s.delta_t.toFixed(4)} s`, 'the time step'), ' · ',
      piece(`mass ×${formatNumber(s.mass_scale)}`, 'the factor on every vertex\'s mass (no unit)')], { detail: true }),
    line([`${s.method}${s.plain_first ? ' (plain first)' : ''} · `,
      piece(`≤ ${s.iterations} iterations`, 'the most local/global iterations a step may take'),
      ` · ${tolerance} · start ${s.start === 'inertial' ? 'from momentum' : 'where it is'}`],
    { fine: s.solver !== null }),
    line([s.refactor_ms === null ? 'Q factored once, when the scene loaded'
      : piece(`Q rebuilt and refactored in ${s.refactor_ms.toFixed(1)} ms`,
        'the time the last change of k, Δt, the masses or the pins took to rebuild Q and factor it again')],
    { fine: s.refactor_ms === null }),
    line([piece(`${s.ms_per_step.toFixed(2)} ms/step`, 'milliseconds a step takes, averaged over about the last 10'),
      ' · ', piece(`${s.steps_per_second.toFixed(1)} steps/s`, 'steps over the last second (real time: 1/Δt)')],
    { detail: true }),
    line([piece(`step ${s.steps}`, 'steps since the start or the last reset'), ' · ',
      piece(`t ${s.time.toFixed(2)} s`, 'simulated time: the sum of every step\'s own Δt'), ' · ',
      piece(`energy ${formatNumber(s.energy)} J`, 'mechanical energy: kinetic, the springs\' and gravity\'s (0 at rest)'),
      ` · wind ${s.wind ? 'on' : 'off'}`]),
  ];
}

/** Whether it runs, the work in progress, the last step, what happened. */
function describeWork(s) {
  let running;
  if (!s.animating) {
    running = s.steps === 0 ? 'paused at rest: ▶ play (A) or step (space)' : 'paused';
  } else if (!s.watched) {
    running = 'waiting for a page to show it';
  } else {
    running = `animating (while a page shows it: ${s.pages} now)`;
  }
  const lines = [line([running])];
  if (s.busy) {
    lines.push(line([`${s.busy}: `, piece(`${(s.busy_ms / 1000).toFixed(1)} s so far`, 'how long it has run'),
      ' · ■ stop (Esc) cancels it']));
    if (s.queued > 0) {
      lines.push(line([piece(`${s.queued} command(s) wait for it`, 'commands queued behind the work in progress')]));
    }
  }
  if (state.waiting) lines.push(line([`${state.waiting}: waits for the step in progress, applied after it`]));
  const last = s.history.length > 0 ? s.history[s.history.length - 1] : null;
  if (last) {
    const [reason, why] = STOP_REASONS[last.stop] || [last.stop, last.stop];
    const gradient = last.relative_gradient === null
      ? ['relative gradient not measured']
      : [piece(`relative gradient ${last.relative_gradient.toPrecision(2)}`, RELATIVE_GRADIENT)];
    lines.push(line(['last step: ', piece(`${last.iterations} iterations (${reason})`,
      `local/global iterations it ran; it stopped because ${why}`), ', ', ...gradient], { detail: true }));
  }
  if (s.dragged !== null) {
    lines.push(line([piece(`dragging vertex ${s.dragged + 1}`, 'the vertex pulled, counted from 1 as the OBJ does')]));
  }
  if (s.note) lines.push(line([s.note]));
  if (s.error) lines.push(line([`stopped: ${s.error}`]));
  if (state.refusal) lines.push(line([`refused: ${state.refusal}`]));
  return lines;
}

/** The compared simulation: how it is solved, its time per step. */
function describeComparison(s) {
  const c = s.compare;
  if (!c) return [];
  const where = state.layout === 'beside' ? 'right' : 'orange wireframe';
  const lines = [
    line([piece(`compared with (${where}): ${solvedBy(c.solver, c.backend, c.method)}`, `runs ${c.functions}`)]),
    line([`  ${c.functions}`], { path: true }),
  ];
  const last = c.history.length > 0 ? c.history[c.history.length - 1] : null;
  if (c.solver === 'frames') {
    const distance = last && last.distance !== null
      ? piece(`distance now ${formatNumber(last.distance)} m`,
        'the largest distance between a vertex of ours and the same vertex of your frame of this step')
      : (c.ended ? `your frames end at step ${s.frames ? s.frames.steps : '?'}; ours goes on alone` : 'no step yet');
    lines.push(line(['  ', distance]));
  } else {
    lines.push(line(['  ', piece(`${c.ms_per_step.toFixed(1)} ms/step`, 'its time per step, averaged'),
      ` (this one ${s.ms_per_step.toFixed(1)})`, ' · ', piece(`energy ${formatNumber(c.energy)} J`,
        'its mechanical energy now')], { detail: true }));
  }
  return lines;
}

function formatNumber(x) {
  if (x === 0) return '0';
  if (Math.abs(x) >= 1e4 || Math.abs(x) < 1e-2) return x.toExponential(1);
  return String(Number(x.toPrecision(3)));
}

// ---------------------------------------------------------------------------
// The plot (plot.js), under the statistics.

const plotCanvas = document.getElementById('plot');

function updatePlot() {
  const s = state.status;
  if (!s || plotCanvas.clientWidth === 0) return;
  const font = document.body.classList.contains('large') ? 16 : 12;
  const panels = plotPanels(s, simulationNames(s));
  window.viewer.plotText = drawPlot(plotCanvas, panels, font);
  plotCanvas.title = panels.map((panel) => `${panel.title}: ${panel.hover}`).join('\n');
  window.viewer.plotPoints = s.history.length;
}

// ---------------------------------------------------------------------------
// Labels over the cloths: when comparing, each cloth has its solver's name
// above it, on the canvas (over: the wireframe's above the cloth's).

const clothLabels = [document.getElementById('label-0'), document.getElementById('label-1')];

function labelFont() {
  return document.body.classList.contains('large') ? 18 : 14;
}

/** Puts each label above its cloth as `matrices` draw it. */
function placeLabels(matrices) {
  const s = state.status;
  const comparing = Boolean(s && s.compare && state.second && state.positions);
  const names = comparing ? simulationNames(s) : [];
  clothLabels.forEach((label, set) => {
    label.hidden = !comparing;
    if (!comparing) return;
    const box = projectedBox(set, matrices);
    const overlaid = state.layout !== 'beside';
    label.textContent = set === 1 && overlaid ? `orange wireframe: ${names[1]}` : names[set];
    const y = box.top - 4 - (overlaid && set === 1 ? 1.9 * labelFont() : 0);
    const half = label.offsetWidth / 2;
    label.style.left = `${Math.min(Math.max(box.x, half + 4), canvas.clientWidth - half - 4)}px`;
    label.style.top = `${Math.max(y, 1.7 * labelFont())}px`;
  });
  // Two cloths close together: the second label goes above the first.
  const [a, b] = clothLabels.map((label) => label.getBoundingClientRect());
  if (comparing && a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom) {
    clothLabels[1].style.top = `${parseFloat(clothLabels[0].style.top) - 1.9 * labelFont()}px`;
  }
}

/** The top and the horizontal middle of simulation `set` on the screen. */
function projectedBox(set, matrices) {
  const positions = set === 1 ? state.second : state.positions;
  const offset = set === 1 ? secondOffset() : [0, 0, 0];
  let [left, right, top] = [Infinity, -Infinity, Infinity];
  for (let i = 0; i < positions.length; i += 3) {
    const p = project([positions[i] + offset[0], positions[i + 1] + offset[1], positions[i + 2] + offset[2]], matrices);
    if (!p) continue;
    left = Math.min(left, p.x);
    right = Math.max(right, p.x);
    top = Math.min(top, p.y);
  }
  return { x: (left + right) / 2, top };
}

// ---------------------------------------------------------------------------
// The controls panel: buttons (the keys' commands; reset, which returns to
// the scene as it loaded, and restart, which keeps the settings; ■ stop,
// which stops whatever runs; large print; the sliders shown or not; on a
// phone, the drawer), the scene picker, the solve picker (the assignment,
// the handout's code dense or sparse, the fast mode: `--textbook` and
// `--accuracy` on the command line), "compare" and how the compared
// simulation is drawn, sliders for k (log scale), Δt, the mass scale (log
// scale) and the iterations, and, for experts, the method, the two
// tolerances, the floor and the start. A slider shows its value while it
// moves and sends set_parameters when let go. Every control sends only
// what it changes: the others are the server's values, not read back from
// controls that would round them. A control keeps what the user chose
// until the server has answered, then shows the server's value.

const controls = {
  play: document.getElementById('play'),
  step: document.getElementById('step'),
  reset: document.getElementById('reset'),
  restart: document.getElementById('restart'),
  stop: document.getElementById('stop'),
  drawer: document.getElementById('drawer'),
  wind: document.getElementById('wind'),
  springs: document.getElementById('springs'),
  fit: document.getElementById('fit'),
  large: document.getElementById('large'),
  more: document.getElementById('more'),
  help: document.getElementById('help-button'),
  scene: document.getElementById('scene'),
  solver: document.getElementById('solver'),
  compare: document.getElementById('compare'),
  layout: document.getElementById('layout'),
  method: document.getElementById('method'),
  tolerance: document.getElementById('tolerance'),
  energyTolerance: document.getElementById('energy_tolerance'),
  atLeastPlain: document.getElementById('at_least_plain'),
  start: document.getElementById('start'),
};

/** Each slider: how its position maps to the parameter and back, and its
 *  value with its unit. */
const SLIDERS = {
  k: { toValue: (x) => 10 ** x, toSlider: Math.log10, show: (v) => `${formatNumber(v)} N/m` },
  delta_t: { toValue: (x) => x, toSlider: (v) => v, show: (v) => `${v.toFixed(4)} s` },
  mass_scale: { toValue: (x) => 10 ** x, toSlider: Math.log10, show: (v) => `×${formatNumber(v)}` },
  iterations: { toValue: (x) => Math.round(x), toSlider: (v) => v, show: String },
};

function sliderValue(name) {
  const input = document.getElementById(name);
  return SLIDERS[name].toValue(Number(input.value));
}

/** Sends the parameters: the server's values, with the one of slider
 *  `name` changed. */
function sendParameters(name) {
  const s = state.status;
  const parameters = { k: s.k, delta_t: s.delta_t, mass_scale: s.mass_scale, iterations: s.iterations };
  parameters[name] = sliderValue(name);
  return send({ command: 'set_parameters', ...parameters }, name);
}

/** A tolerance slider's position (decades, 0: off) as the value sent. */
function fromDecades(decades) {
  return decades > 0 ? 10 ** -decades : null;
}

/** A tolerance (`null`: off) as a slider's position in decades. */
function toDecades(tolerance) {
  return tolerance === null ? 0 : Math.round(-Math.log10(tolerance));
}

/** The server's method and rules, with the one of control `changed`
 *  (method, tolerance, energy_tolerance, at_least_plain or start) taken
 *  from the page. */
function sendMethod(changed) {
  const s = state.status;
  const method = {
    method: s.method, tolerance: s.tolerance, energy_tolerance: s.energy_tolerance,
    at_least_plain: s.at_least_plain, start: s.start,
  };
  const fromPage = {
    method: () => controls.method.value,
    tolerance: () => fromDecades(Number(controls.tolerance.value)),
    energy_tolerance: () => fromDecades(Number(controls.energyTolerance.value)),
    at_least_plain: () => (controls.atLeastPlain.checked ? 50 : null),
    start: () => (controls.start.checked ? 'inertial' : 'current'),
  };
  method[changed] = fromPage[changed]();
  return send({ command: 'set_method', ...method }, changed);
}

/** A picker's value, `solver` or `solver:backend`, as a command's fields. */
function solverChoice(value) {
  const [solver, backendName] = value.split(':');
  return backendName ? { solver, backend: backendName } : { solver };
}

for (const name of Object.keys(SLIDERS)) {
  const input = document.getElementById(name);
  const output = document.getElementById(`${name}-value`);
  input.addEventListener('input', () => { output.textContent = SLIDERS[name].show(sliderValue(name)); });
  input.addEventListener('change', () => { if (state.status) sendParameters(name); });
}

const BUTTON_COMMANDS = {
  play: 'toggle_animation', step: 'step', reset: 'reset', restart: 'restart', wind: 'toggle_wind',
  springs: 'toggle_springs', stop: 'cancel',
};
for (const [id, command] of Object.entries(BUTTON_COMMANDS)) {
  controls[id].addEventListener('click', () => send({ command }));
}
controls.fit.addEventListener('click', fitToCloth);
controls.help.addEventListener('click', () => toggleHelp());
controls.large.addEventListener('click', () => setLargePrint(!document.body.classList.contains('large')));
controls.more.addEventListener('click', () => document.body.classList.toggle('settings-open'));
controls.drawer.addEventListener('click', () => document.body.classList.toggle('drawer-open'));
controls.scene.addEventListener('change', () => {
  send({ command: 'load_scene', scene: Number(controls.scene.value) }, 'scene');
});
controls.solver.addEventListener('change', () => {
  if (controls.solver.value) send({ command: 'set_solver', ...solverChoice(controls.solver.value) }, 'solver');
});
controls.compare.addEventListener('change', () => {
  const value = controls.compare.value;
  if (!value) {
    send({ command: 'compare', with: null }, 'compare');
    return;
  }
  const { solver, backend: backendName } = solverChoice(value);
  send({ command: 'compare', with: solver, ...(backendName ? { backend: backendName } : {}) }, 'compare');
});
controls.layout.addEventListener('change', () => {
  state.layout = controls.layout.value;
  frameAfresh(); // the pair as it is now drawn
});
controls.method.addEventListener('change', () => sendMethod('method'));
controls.tolerance.addEventListener('change', () => sendMethod('tolerance'));
controls.energyTolerance.addEventListener('change', () => sendMethod('energy_tolerance'));
controls.atLeastPlain.addEventListener('change', () => sendMethod('at_least_plain'));
controls.start.addEventListener('change', () => sendMethod('start'));
controls.tolerance.addEventListener('input', () => {
  document.getElementById('tolerance-value').textContent = toleranceText(fromDecades(Number(controls.tolerance.value)));
});
controls.energyTolerance.addEventListener('input', () => {
  document.getElementById('energy_tolerance-value').textContent =
    toleranceText(fromDecades(Number(controls.energyTolerance.value)));
});

function toleranceText(tolerance) {
  return tolerance === null ? 'off' : formatNumber(tolerance);
}

/** Is `control` (an element) being handled: its command not answered
 *  yet, or a slider held? Its value is then the user's, not the status's. */
function handling(control) {
  return state.pending.has(control.id)
    || (control.type === 'range' && document.activeElement === control && state.sliderHeld);
}

/** Shows the status in the controls, but in those being handled. */
function syncControls() {
  const s = state.status;
  if (!s) return;
  controls.play.textContent = s.animating ? '❚❚ pause' : '▶ play';
  controls.play.classList.toggle('on', s.animating);
  const running = Boolean(s.busy) || s.animating;
  controls.stop.disabled = !running;
  controls.stop.classList.toggle('on', Boolean(s.busy));
  controls.wind.classList.toggle('on', s.wind);
  controls.springs.classList.toggle('on', s.show_springs);
  syncList(controls.scene, s.scenes.map((name, i) => [String(i), name]), String(s.scene_index));
  syncList(controls.method, s.methods.map((name) => [name, name]), s.method);
  syncSolveLabels(s);
  const solver = s.solver === 'textbook' ? `textbook:${s.backend}` : (s.solver || '');
  syncPicker(controls.solver, solver);
  const compare = !s.compare ? '' : s.compare.solver === 'textbook' ? `textbook:${s.compare.backend}`
    : (s.compare.solver || '');
  syncPicker(controls.compare, compare);
  controls.layout.disabled = !s.compare || fallback; // the server's images draw it beside
  syncRules(s);
  for (const name of Object.keys(SLIDERS)) {
    const input = document.getElementById(name);
    if (handling(input)) continue;
    input.value = String(SLIDERS[name].toSlider(s[name]));
    document.getElementById(`${name}-value`).textContent = SLIDERS[name].show(s[name]);
  }
}

/** The pickers' words that depend on the scene: what the dense setup
 *  takes, and whether the frames of --frames can be compared with. */
function syncSolveLabels(s) {
  const gigabytes = (s.dense_memory.match(/: ([0-9.]+ GB)/) || [])[1] || '';
  const dense = s.dense_fits ? `the handout's code, dense (${gigabytes})`
    : `the handout's code, dense (${gigabytes}: over the limit)`;
  for (const select of [controls.solver, controls.compare]) {
    const option = select.querySelector('option[value="textbook:dense"]');
    option.hidden = !s.dense_memory; // a page that runs the simulation itself has no dense path
    option.textContent = dense;
    option.title = `${s.dense_memory}; Esc stops its setup`;
    const fast = select.querySelector('option[value="accuracy-assignment"]');
    fast.title = FAST_MODE;
  }
  const frames = controls.compare.querySelector('option[value="frames"]');
  frames.hidden = !s.frames || s.scene_index !== 0;
  if (s.frames) {
    frames.textContent = `your frames (${s.frames.steps} steps)`;
    frames.title = `the frames in ${s.frames.folder}, played back one a step from rest`;
  }
}

/** The expert's rules: start, floor and the two tolerances. */
function syncRules(s) {
  if (!handling(controls.start)) controls.start.checked = s.start === 'inertial';
  if (!handling(controls.atLeastPlain)) controls.atLeastPlain.checked = s.at_least_plain !== null;
  for (const [input, name] of [[controls.tolerance, 'tolerance'], [controls.energyTolerance, 'energy_tolerance']]) {
    if (handling(input)) continue;
    input.value = String(toDecades(s[name]));
    document.getElementById(`${name}-value`).textContent = toleranceText(s[name]);
  }
}

/** A select listing `entries` ([value, label]), showing `value`. */
function syncList(select, entries, value) {
  if (select.options.length !== entries.length) {
    select.replaceChildren(...entries.map(([v, label]) => new Option(label, v)));
  }
  if (!handling(select)) select.value = value;
}

/** A fixed picker showing `value` (`''`: the expert's own settings). */
function syncPicker(select, value) {
  if (!handling(select)) select.value = value;
}

window.addEventListener('pointerdown', () => { state.sliderHeld = true; });
window.addEventListener('pointerup', () => { state.sliderHeld = false; });

// ---------------------------------------------------------------------------
// The layout: large print (on by default on a window at most
// LARGE_PRINT_WIDTH wide), a phone's (narrower than NARROW_WIDTH: the
// drawer), the sliders shown (by default in small print).

/** Large print on or off: the page's text at least 16 px. */
function setLargePrint(large) {
  document.body.classList.toggle('large', large);
  controls.large.classList.toggle('on', large);
  fitLayout();
}

/** Follows the window's width: a phone's layout or not. */
function fitLayout() {
  const print = document.body.classList.contains('large') ? 'large' : 'small';
  document.body.classList.toggle('narrow', window.innerWidth < NARROW_WIDTH[print]);
  layoutChanged();
}

/** The panels changed size: the plot is drawn again, the camera frames
 *  the free area that is left. */
function layoutChanged() {
  updatePlot();
  frameAfresh();
}

window.addEventListener('resize', fitLayout);
new ResizeObserver(() => layoutChanged()).observe(document.getElementById('controls'));

// ---------------------------------------------------------------------------
// Help overlay: ? or H shows and hides it, Esc hides it.

const helpOverlay = document.getElementById('help-overlay');

function toggleHelp(show = helpOverlay.hidden) {
  helpOverlay.hidden = !show;
}

helpOverlay.addEventListener('click', () => toggleHelp(false));

// ---------------------------------------------------------------------------
// Keys: as the assignment's viewer, plus shift-R (restart), F (fit), M
// (next method), ?/H (help) and Esc (stop whatever runs, close the help).
// They act whatever control has focus (a slider, a picker, a button just
// clicked), but while typing in a text field; the focused control does
// not also take the key (space does not click the button, a letter does
// not pick an option).

const KEY_COMMANDS = {
  ' ': 'step', // pause and advance one step
  a: 'toggle_animation',
  l: 'toggle_springs',
  r: 'reset',
  R: 'restart',
  w: 'toggle_wind',
};

/** Key M: the next method in the server's list. */
function nextMethod() {
  const s = state.status;
  if (!s) return;
  const next = s.methods[(s.methods.indexOf(s.method) + 1) % s.methods.length];
  send({
    command: 'set_method', method: next, tolerance: s.tolerance,
    energy_tolerance: s.energy_tolerance, at_least_plain: s.at_least_plain,
  });
}

/** Is `target` a field one types text into? */
function typingInto(target) {
  if (target instanceof HTMLTextAreaElement || (target && target.isContentEditable)) return true;
  const notText = ['range', 'checkbox', 'radio', 'button', 'submit', 'reset', 'color', 'file', 'image'];
  return target instanceof HTMLInputElement && !notText.includes(target.type);
}

/** What key `event` does, or null. */
function keyAction(event) {
  const key = event.key.length === 1 && !event.shiftKey ? event.key.toLowerCase() : event.key;
  if (key === '?' || key === 'h' || key === 'H') return () => toggleHelp();
  if (key === 'Escape') {
    return () => {
      toggleHelp(false);
      send({ command: 'cancel' }); // a step, a setup, the animation: whatever runs
    };
  }
  if (key === 'f' || key === 'F') return fitToCloth;
  if (key === 'm' || key === 'M') return nextMethod;
  const command = KEY_COMMANDS[key] || KEY_COMMANDS[key.toLowerCase()];
  if (!command) return null;
  // Holding space keeps stepping; holding another key does not repeat it.
  return () => { if (!event.repeat || command === 'step') send({ command }); };
}

window.addEventListener('keydown', (event) => {
  if (event.ctrlKey || event.metaKey || event.altKey || typingInto(event.target)) return;
  const action = keyAction(event);
  if (!action) return;
  event.preventDefault();
  action();
}, { capture: true });

// A button pressed by space or enter would click again when the key goes up.
window.addEventListener('keyup', (event) => {
  if (event.key === ' ' && !typingInto(event.target)) event.preventDefault();
}, { capture: true });

// ---------------------------------------------------------------------------
// Mouse: drag to orbit, right-drag or ctrl-drag to pan, wheel to zoom
// toward the cursor, shift-drag to pull a vertex.
//
// Picking: every free vertex is projected to the screen with the current
// projection · view matrix; the nearest one within PICK_RADIUS pixels of the
// cursor is taken. While the button is held, the cursor's ray from the eye
// is cut with the plane through that vertex facing the camera, and the
// vertex is pulled toward that point (Simulation::drag_to on the server).

/** Where world point p appears, in CSS pixels from the top left, and its
 *  depth (clip w); null when it is behind the camera. */
function project(p, matrices) {
  const [x, y, , w] = transform(matrices.viewProjection, p);
  if (w <= 0) return null;
  return {
    x: (x / w + 1) / 2 * canvas.clientWidth,
    y: (1 - y / w) / 2 * canvas.clientHeight,
    depth: w,
  };
}

/** Where simulated vertex i of simulation `set` (1: the compared one,
 *  where it is drawn) appears; null when it is behind the camera. */
function screenPosition(i, matrices, set = 0) {
  const positions = set === 1 ? state.second : state.positions;
  const offset = set === 1 ? secondOffset() : [0, 0, 0];
  return project(add(Array.from(positions.subarray(3 * i, 3 * i + 3)), offset), matrices);
}

/** The free vertex nearest to the cursor (x, y) on screen, in either
 *  simulation drawn, or null: { vertex, set }. */
function pickVertex(x, y, matrices, radius = PICK_RADIUS) {
  let best = null;
  let bestDistance = radius;
  const pinned = pinnedVertices();
  const sets = state.second && state.layout === 'beside' ? [0, 1] : [0];
  for (const set of sets) {
    for (let i = 0; i < state.scene.n; i++) {
      if (pinned[i]) continue;
      const s = screenPosition(i, matrices, set);
      if (!s) continue;
      const distance = Math.hypot(s.x - x, s.y - y);
      if (distance < bestDistance) {
        bestDistance = distance;
        best = { vertex: i, set };
      }
    }
  }
  return best;
}

/** Where the ray from the eye through cursor (x, y) meets the plane
 *  through `point` facing the camera. */
function pointUnderCursor(x, y, point, matrices) {
  // The shifted lens moves the centre of view by camera.shift.
  const ndcX = 2 * x / canvas.clientWidth - 1 - camera.shift[0];
  const ndcY = 1 - 2 * y / canvas.clientHeight - camera.shift[1];
  const tanY = Math.tan(camera.fovY / 2);
  // The ray's direction: forward (−back), plus the cursor's offset on the
  // image plane at distance 1.
  const direction = add(scale(matrices.back, -1),
    add(scale(matrices.right, ndcX * tanY * matrices.aspect), scale(matrices.up, ndcY * tanY)));
  const t = dot(sub(point, matrices.eye), matrices.back) / dot(direction, matrices.back);
  return add(matrices.eye, scale(direction, t));
}

// Drag commands go out in order, and at most one drag_to waits at a time
// (always with the latest target), so a slow server never falls behind.
let dragQueue = Promise.resolve();
let dragToWaiting = false;

function queueDragCommand(body) {
  dragQueue = dragQueue.then(() => sendCommand(body)).catch(() => setConnected(false));
}

function queueDragTo() {
  if (dragToWaiting) return;
  dragToWaiting = true;
  dragQueue = dragQueue.then(() => {
    dragToWaiting = false;
    return sendCommand({ command: 'drag_to', target: state.dragTarget });
  }).catch(() => setConnected(false));
}

/** Starts pulling the free vertex nearest to (x, y); false when none. In
 *  either simulation when comparing: the same vertex of both is pulled to
 *  the same target (in the scene's coordinates, without the offset at
 *  which the compared one is drawn). */
function startVertexDrag(x, y, radius) {
  const matrices = cameraMatrices(aspectRatio());
  const picked = pickVertex(x, y, matrices, radius);
  if (picked === null) return false;
  const { vertex, set } = picked;
  const positions = set === 1 ? state.second : state.positions;
  const offset = set === 1 ? secondOffset() : [0, 0, 0];
  const target = Array.from(positions.subarray(3 * vertex, 3 * vertex + 3));
  state.dragged = { vertex, set, offset, point: add(target, offset) };
  state.dragTarget = target;
  canvas.classList.add('dragging-vertex');
  queueDragCommand({ command: 'drag_start', vertex, target });
  return true;
}

/** Pulls the dragged vertex toward the point under (x, y). */
function moveVertexDrag(x, y) {
  const matrices = cameraMatrices(aspectRatio());
  const point = pointUnderCursor(x, y, state.dragged.point, matrices);
  state.dragTarget = sub(point, state.dragged.offset);
  queueDragTo();
}

function endVertexDrag() {
  if (!state.dragged) return;
  state.dragged = null;
  state.dragTarget = null;
  canvas.classList.remove('dragging-vertex');
  queueDragCommand({ command: 'drag_end' });
}

function orbit(dx, dy) {
  camera.azimuth -= dx * 0.01;
  const limit = Math.PI / 2 - 0.01;
  camera.elevation = Math.max(-limit, Math.min(limit, camera.elevation + dy * 0.01));
  takeCamera();
}

let mouse = null; // { mode: 'orbit' | 'pan', x, y } while a button is held

canvas.addEventListener('contextmenu', (event) => event.preventDefault());

canvas.addEventListener('mousedown', (event) => {
  if (!state.positions) return;
  if (event.shiftKey && event.button === 0) {
    startVertexDrag(event.offsetX, event.offsetY, PICK_RADIUS);
  } else {
    const panning = event.button === 2 || (event.button === 0 && event.ctrlKey);
    mouse = { mode: panning ? 'pan' : 'orbit', x: event.clientX, y: event.clientY };
  }
  event.preventDefault();
});

window.addEventListener('mousemove', (event) => {
  if (state.dragged) {
    const rect = canvas.getBoundingClientRect();
    moveVertexDrag(event.clientX - rect.left, event.clientY - rect.top);
  } else if (mouse) {
    const dx = event.clientX - mouse.x;
    const dy = event.clientY - mouse.y;
    mouse.x = event.clientX;
    mouse.y = event.clientY;
    if (mouse.mode === 'pan') pan(dx, dy); else orbit(dx, dy);
  }
});

window.addEventListener('mouseup', () => {
  endVertexDrag();
  mouse = null;
});

canvas.addEventListener('wheel', (event) => {
  zoomToward(event.offsetX, event.offsetY, Math.exp(event.deltaY * 0.001));
  event.preventDefault();
}, { passive: false });

// ---------------------------------------------------------------------------
// Touch: one finger orbits, two fingers pinch-zoom (toward their midpoint)
// and pan, a finger held still for LONG_PRESS_MS pulls the nearest vertex.

let touch = null; // { x, y, distance, timer, moved } while fingers are down

function touchPoints(event) {
  const rect = canvas.getBoundingClientRect();
  return Array.from(event.touches, (t) => ({ x: t.clientX - rect.left, y: t.clientY - rect.top }));
}

canvas.addEventListener('touchstart', (event) => {
  event.preventDefault();
  if (!state.positions) return;
  const points = touchPoints(event);
  if (touch?.timer) clearTimeout(touch.timer);
  if (points.length === 1) {
    const [p] = points;
    touch = { x: p.x, y: p.y, moved: false, timer: null };
    touch.timer = setTimeout(() => {
      if (touch && !touch.moved) startVertexDrag(touch.x, touch.y, 2 * PICK_RADIUS);
    }, LONG_PRESS_MS);
  } else if (points.length === 2) {
    endVertexDrag();
    const [a, b] = points;
    touch = { x: (a.x + b.x) / 2, y: (a.y + b.y) / 2, distance: Math.hypot(a.x - b.x, a.y - b.y), moved: true };
  }
}, { passive: false });

canvas.addEventListener('touchmove', (event) => {
  event.preventDefault();
  if (!touch) return;
  const points = touchPoints(event);
  if (points.length === 1) {
    const [p] = points;
    if (Math.hypot(p.x - touch.x, p.y - touch.y) > 8) touch.moved = true;
    if (state.dragged) {
      moveVertexDrag(p.x, p.y);
    } else if (touch.moved) {
      orbit(p.x - touch.x, p.y - touch.y);
      touch.x = p.x;
      touch.y = p.y;
    }
  } else if (points.length === 2 && touch.distance) {
    const [a, b] = points;
    const x = (a.x + b.x) / 2;
    const y = (a.y + b.y) / 2;
    const distance = Math.max(1, Math.hypot(a.x - b.x, a.y - b.y));
    pan(x - touch.x, y - touch.y);
    zoomToward(x, y, touch.distance / distance);
    touch = { ...touch, x, y, distance };
  }
}, { passive: false });

canvas.addEventListener('touchend', (event) => {
  event.preventDefault();
  if (event.touches.length === 0) {
    if (touch?.timer) clearTimeout(touch.timer);
    endVertexDrag();
    touch = null;
  }
}, { passive: false });

// ---------------------------------------------------------------------------
// Start: fetch the status and the scene, then draw on every animation frame
// of the browser (with WebGL, or the server's images without it).

// ---------------------------------------------------------------------------
// A scene of the user's own, where the backend can open one (a page that
// runs the simulation itself, src/web/backend.js): its JSON, the OBJ and
// the PNG it names, picked with "open…" or dropped on the page. A file
// that cannot be read is refused in the command line's words, shown on the
// overlay.

async function openFiles(files) {
  if (files.length === 0) return;
  const { ok, answer } = await backend.openFiles(files);
  state.status = ok ? answer : state.status;
  state.refusal = ok ? null : `your scene: ${answer.error}`;
  window.viewer.lastOpen = { ok, error: ok ? null : answer.error };
  onStatus();
}

if (backend.openFiles) {
  const openButton = document.getElementById('open');
  const picker = document.getElementById('open-files');
  openButton.hidden = false;
  openButton.addEventListener('click', () => picker.click());
  picker.addEventListener('change', () => {
    openFiles(Array.from(picker.files));
    picker.value = ''; // the same files can be picked again
  });
  window.addEventListener('dragover', (event) => event.preventDefault());
  window.addEventListener('drop', (event) => {
    event.preventDefault();
    openFiles(Array.from(event.dataTransfer.files));
  });
}

function everyAnimationFrame() {
  if (!state.loadingScene && state.scene) {
    pollFrame();
    if (fallback) {
      drawImage();
    } else if (gpu) {
      if (state.positions) frameScene(aspectRatio());
      // Drawn again only when something drawn changed: an idle page
      // leaves the processor to the simulation.
      const key = drawKey();
      if (key !== lastDrawKey) draw();
      lastDrawKey = key;
    }
  }
  requestAnimationFrame(everyAnimationFrame);
}

let lastDrawKey = null;

/** Everything the WebGL picture depends on, as one string. */
function drawKey() {
  const s = state.status;
  return [state.serial, camera.azimuth, camera.elevation, camera.distance, ...camera.target, ...camera.shift,
    canvas.clientWidth, canvas.clientHeight, window.devicePixelRatio, s && s.show_springs, gpu.texture !== null,
    state.layout, state.dragTarget && state.dragTarget.join(), state.second !== null,
    document.body.className, s && s.compare && s.compare.solver].join('|');
}

async function start() {
  setLargePrint(window.innerWidth <= LARGE_PRINT_WIDTH);
  document.body.classList.toggle('settings-open', !document.body.classList.contains('large'));
  await pollStatus();
  state.sceneSerial = state.status ? state.status.scene_serial : 0;
  await loadScene();
  setInterval(pollStatus, STATUS_PERIOD);
  window.viewer.ready = true;
  requestAnimationFrame(everyAnimationFrame);
}

start().catch((error) => {
  window.viewer.error = String(error);
  statsText.textContent = `cannot start: ${error.message}`;
});
