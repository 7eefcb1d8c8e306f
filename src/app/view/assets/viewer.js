// The page of `masssprings view`: draws, with plain WebGL, the simulation
// that runs in the masssprings process, and sends it keys and drags.
//
// Data flow (see src/app/view/api.rs):
//   GET  /api/scene         once per scene: triangles, springs, pins, texture
//                           coordinates (again when status.scene_serial changes)
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
//   POST /api/command       keys, buttons, sliders, pickers, drags, stop
//
// Each tab keeps its own camera; every command acts on the one simulation
// the server runs, so two tabs see the same cloth.
//
// Drawing, back to front: a background gradient, the mesh (textured or
// flat, lit on both sides), then, when shown (key L), the springs as lines
// and the point masses as discs sized to the mesh spacing, and always the
// pinned vertices as silver discs. When comparing, the second simulation
// beside the first (the same drawing, moved along x) or as an orange
// wireframe over it.
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
/** The random name this page gives itself on /api/frame. */
const PAGE_ID = Math.floor(Math.random() * 2 ** 31) + 1;
/** Milliseconds between two status polls. */
const STATUS_PERIOD = 250;

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
// is up. When a scene loads it frames the cloth, and until the user moves
// the camera it keeps framing everything the cloth has occupied since (like
// the renderer, which frames all frames). F frames the cloth as it is now.
//
// Framing fills the free part of the window, not the whole canvas: the
// panels cover its left and right sides. The free area is the largest of
// the rectangles between the panels, below both, and below the statistics
// left of the controls that the scene fits best; the lens is shifted
// (`shift`, in normalised device coordinates) so that the scene's centre
// lands in its middle, and the distance is the least at which the scene
// fits its width and height with the margin.

const camera = {
  azimuth: LOOK.azimuthDegrees * Math.PI / 180,
  elevation: LOOK.elevationDegrees * Math.PI / 180,
  fovY: LOOK.fieldOfViewDegrees * Math.PI / 180,
  target: [0, 0, 0],
  distance: 1,
  shift: [0, 0],
  autoFrame: true,
  box: emptyBox(),
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

/** Grows the camera's box by `positions`, moved by `offset`. */
function growBox(positions, offset = [0, 0, 0]) {
  const { min, max } = camera.box;
  for (let i = 0; i < positions.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      min[k] = Math.min(min[k], positions[i + k] + offset[k]);
      max[k] = Math.max(max[k], positions[i + k] + offset[k]);
    }
  }
}

/** Grows the box by every simulation shown, where it is drawn. */
function growBoxByShown() {
  if (state.positions) growBox(state.positions);
  if (state.second) growBox(state.second, secondOffset());
}

/** The rectangles of the canvas (CSS pixels) that no panel covers, each
 *  { left, top, width, height }; the whole canvas when none is left. */
function freeAreas() {
  const width = canvas.clientWidth;
  const height = canvas.clientHeight;
  const gap = 8;
  const o = overlay.getBoundingClientRect();
  const c = document.getElementById('controls').getBoundingClientRect();
  const bottom = document.getElementById('help').getBoundingClientRect().top - gap;
  const rectangle = (left, top, right, low) => ({ left, top, width: right - left, height: low - top });
  const areas = [
    rectangle(o.right + gap, 0, c.left - gap, bottom), // between the panels
    rectangle(0, Math.max(o.bottom, c.bottom) + gap, width, bottom), // below both
    rectangle(0, o.bottom + gap, c.left - gap, bottom), // below the statistics
  ].filter((r) => r.width >= 80 && r.height >= 80);
  return areas.length > 0 ? areas : [rectangle(0, 0, width, height)];
}

/** The distance at which the box fits `area` (a rectangle of the canvas)
 *  with the margin, for the current angles (as src/app/render/camera.rs
 *  frames the whole image). */
function distanceToFit(area, aspect, target) {
  const { min, max } = camera.box;
  const { right, up, back } = cameraFrame();
  const tanY = Math.tan(camera.fovY / 2) * area.height / Math.max(1, canvas.clientHeight);
  const tanX = Math.tan(camera.fovY / 2) * aspect * area.width / Math.max(1, canvas.clientWidth);
  let distance = 1e-6;
  for (let corner = 0; corner < 8; corner++) {
    const p = [0, 1, 2].map((k) => ((corner >> k) & 1 ? max[k] : min[k]));
    const o = sub(p, target);
    const fit = Math.max(Math.abs(dot(o, right)) / tanX, Math.abs(dot(o, up)) / tanY);
    distance = Math.max(distance, dot(o, back) + LOOK.margin * fit);
  }
  return distance;
}

/** Aims at the box: target = its centre, in the middle of the free area
 *  where it is largest, at the least distance at which it fits there. */
function aimAtBox(aspect) {
  const { min, max } = camera.box;
  if (!(min[0] <= max[0])) return;
  const target = scale(add(min, max), 0.5);
  let best = null;
  for (const area of freeAreas()) {
    const distance = distanceToFit(area, aspect, target);
    if (!best || distance < best.distance) best = { area, distance };
  }
  const { area, distance } = best;
  camera.target = target;
  camera.distance = distance;
  camera.shift = [
    2 * (area.left + area.width / 2) / Math.max(1, canvas.clientWidth) - 1,
    1 - 2 * (area.top + area.height / 2) / Math.max(1, canvas.clientHeight),
  ];
  window.viewer.framedArea = area;
}

/** While the camera is automatic, frames everything seen so far. */
function frameScene(aspect) {
  if (!camera.autoFrame) return;
  growBoxByShown();
  aimAtBox(aspect);
}

/** Key F: frames the cloth as it is now (and stays there). */
function fitToCloth() {
  if (!state.positions) return;
  camera.box = emptyBox();
  growBoxByShown();
  aimAtBox(aspectRatio());
  camera.autoFrame = false;
  window.viewer.fits++;
}

/** Moves the target by (dx, dy) CSS pixels across the screen. */
function pan(dx, dy) {
  const { right, up } = cameraFrame();
  const worldPerPixel = 2 * camera.distance * Math.tan(camera.fovY / 2) / Math.max(1, canvas.clientHeight);
  camera.target = add(camera.target, add(scale(right, -dx * worldPerPixel), scale(up, dy * worldPerPixel)));
  camera.autoFrame = false;
}

/** Zooms by `factor` (< 1: closer) toward the point under (x, y): eye and
 *  target both move toward it, so that point stays under the cursor. */
function zoomToward(x, y, factor) {
  const matrices = cameraMatrices(aspectRatio());
  const anchor = pointUnderCursor(x, y, camera.target, matrices);
  camera.target = add(anchor, scale(sub(camera.target, anchor), factor));
  camera.distance *= factor;
  camera.autoFrame = false;
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
  dragged: null, // { vertex, point, offset } while shift-dragging
  dragTarget: null, // where the dragged vertex is pulled to
  sceneSerial: null, // status.scene_serial of the scene drawn
  loadingScene: false,
  refusal: null, // why the last command was refused
  waiting: null, // a command that waits for the step in progress
  sliderHeld: false,
  layout: 'beside', // how the compared simulation is drawn: beside, overlay
};

// What tests (tests/browser) read.
window.viewer = {
  ready: false, framesReceived: 0, framesDrawn: 0, textureLoaded: false, error: null,
  fits: 0, scenesLoaded: 0, plotPoints: 0, fallback, imagesDrawn: 0, framedArea: null,
  lastCommand: null, // { command, status, ms } of the last command answered
  state, camera, look: LOOK,
  screenPositionOf: (vertex, set = 0) => screenPosition(vertex, cameraMatrices(aspectRatio()), set),
  freeAreas: () => freeAreas(),
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
 *  it along x (by a little more than the rest shape's diagonal), or over
 *  it. */
function secondOffset() {
  if (state.layout !== 'beside' || !state.scene) return [0, 0, 0];
  return [1.1 * Math.max(state.scene.diagonal, 1e-3), 0, 0];
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
  fetch(`/api/image?${key}`, { cache: 'no-store' })
    .then((response) => (response.ok ? response.blob() : Promise.reject(new Error(`image: ${response.status}`))))
    .then((blob) => createImageBitmap(blob))
    .then((bitmap) => {
      imageView.context = imageView.context || canvas.getContext('2d');
      imageView.context.drawImage(bitmap, 0, 0, canvas.width, canvas.height);
      if (state.dragged && state.dragTarget) drawDragMarker2d(imageView.context);
      imageView.key = key;
      window.viewer.imagesDrawn++;
      window.viewer.framesDrawn++;
    })
    .catch((error) => { window.viewer.error = String(error); })
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
// Talking to the server. Every command is answered within half a second:
// 200 applied, 409 refused (the reason is shown), or 202: it waits for the
// step in progress and is applied after it (a refusal then shows in the
// status's note); the overlay says which, and ■ stop (Esc) cancels the
// step.

async function sendCommand(body) {
  const started = performance.now();
  const response = await fetch('/api/command', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  const answer = await response.json();
  window.viewer.lastCommand = { command: body.command, status: response.status, ms: performance.now() - started };
  if (response.ok) {
    state.status = answer;
    state.refusal = null;
    const waits = response.status === 202 && response.headers.get('X-Command') === 'waiting';
    state.waiting = waits ? body.command : null;
  } else {
    state.refusal = `${body.command}: ${answer.error}`;
    console.warn('command refused:', body.command, answer.error);
  }
  onStatus();
  return answer;
}

function send(body) {
  return sendCommand(body).catch(() => setConnected(false));
}

/** Asks for the frame after the one we have; 204 means nothing moved. */
async function pollFrame() {
  if (state.frameRequestPending || state.loadingScene) return;
  state.frameRequestPending = true;
  try {
    const since = state.serial === null ? '' : `since=${state.serial}&`;
    const response = await fetch(`/api/frame?${since}page=${PAGE_ID}`, { cache: 'no-store' });
    if (response.status === 200) takeFrame(await response.arrayBuffer());
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
  state.serial = header.getUint32(4, true);
  state.frameSteps = header.getUint32(8, true);
  applyFrame(new Float32Array(bytes, 16, 3 * n), 0);
  if (sets === 2) applyFrame(new Float32Array(bytes, 16 + 12 * n, 3 * n), 1); else state.second = null;
  window.viewer.framesReceived++;
}

async function pollStatus() {
  try {
    const response = await fetch('/api/status', { cache: 'no-store' });
    state.status = await response.json();
    setConnected(true);
  } catch (error) {
    setConnected(false);
  }
  onStatus();
}

function setConnected(connected) {
  state.connected = connected;
  overlay.classList.toggle('disconnected', !connected);
}

/** Fetches the scene the server shows (at start, and when it changes):
 *  the mesh, its texture, a fresh camera framing it. */
async function loadScene() {
  state.loadingScene = true;
  try {
    const response = await fetch('/api/scene', { cache: 'no-store' });
    state.scene = await response.json();
    state.pinnedVertices = null;
    gpu = fallback ? null : createGpuScene(state.scene);
    window.viewer.textureLoaded = fallback;
    if (state.scene.texture && !fallback) loadTexture(`${state.scene.texture}?scene=${state.sceneSerial}`);
    state.positions = null;
    state.second = null;
    state.serial = null;
    camera.box = emptyBox();
    camera.autoFrame = true;
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
  drawPlot();
  syncControls();
}

/** The names of the solvers, as the page says them. */
const SOLVER_LABELS = {
  assignment: 'the assignment (plain, 50 iterations)',
  textbook: 'the handout\'s code',
  'accuracy-assignment': 'assignment accuracy, fast',
  converged: 'converged (L-BFGS, energy tolerance 1e-3)',
};

/** How a simulation is solved, in words: its solver, or its method. */
function solvedBy(solver, backend, method) {
  if (!solver) return `${method} (expert settings)`;
  return solver === 'textbook' ? `${SOLVER_LABELS.textbook}, ${backend}` : SOLVER_LABELS[solver];
}

function updateOverlay() {
  const s = state.status;
  if (!state.connected) {
    statsText.textContent = 'disconnected: is masssprings view still running?';
    return;
  }
  if (!s) return;
  statsText.textContent = [...describeScene(s), ...describeWork(s), ...describeComparison(s)].join('\n');
}

/** The scene, the solve and its path, the parameters, the timings. */
function describeScene(s) {
  const tolerance = (s.tolerance === null ? 'all iterations' : `tolerance ${s.tolerance.toExponential(0)}`)
    + (s.energy_tolerance === null ? '' : ` · energy tolerance ${formatNumber(s.energy_tolerance)}`)
    + (s.at_least_plain === null ? '' : ` · at least plain-${s.at_least_plain}`);
  return [
    `${s.scene} · ${s.backend} · n ${s.n} · springs ${s.springs}`,
    `solve: ${solvedBy(s.solver, s.backend, s.method)}`,
    `  ${s.functions}`,
    `k ${formatNumber(s.k)} · Δt ${s.delta_t.toFixed(4)} s · mass ×${formatNumber(s.mass_scale)}`,
    `${s.method}${s.plain_first ? ' (plain first)' : ''} · ≤ ${s.iterations} iterations · ${tolerance}`
      + ` · start ${s.start === 'inertial' ? 'from momentum' : 'where it is'}`,
    s.refactor_ms === null ? 'Q factored once, when the scene loaded'
      : `Q rebuilt and refactored in ${s.refactor_ms.toFixed(1)} ms`,
    `${s.ms_per_step.toFixed(2)} ms/step · ${s.steps_per_second.toFixed(1)} steps/s`,
    `step ${s.steps} · t ${s.time.toFixed(2)} s · wind ${s.wind ? 'on' : 'off'}`,
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
  const lines = [running];
  if (s.busy) {
    lines.push(`${s.busy}: ${(s.busy_ms / 1000).toFixed(1)} s so far · ■ stop (Esc) cancels it`);
    if (s.queued > 0) lines.push(`${s.queued} command(s) wait for it`);
  }
  if (state.waiting) lines.push(`${state.waiting}: waits for the step in progress, applied after it`);
  const last = s.history.length > 0 ? s.history[s.history.length - 1] : null;
  if (last) {
    const gradient = last.relative_gradient === null ? 'not measured'
      : last.relative_gradient.toExponential(1);
    lines.push(`last step: ${last.iterations} iterations, relative gradient `
      + `${gradient}${last.converged ? ' (converged)' : ''}`);
  }
  if (s.dragged !== null) lines.push(`dragging vertex ${s.dragged + 1}`);
  if (s.note) lines.push(s.note);
  if (s.error) lines.push(`stopped: ${s.error}`);
  if (state.refusal) lines.push(`refused: ${state.refusal}`);
  return lines;
}

/** The compared simulation: how it is solved, its time per step. */
function describeComparison(s) {
  const c = s.compare;
  if (!c) return [];
  return [
    `compared with (${state.layout === 'beside' ? 'right' : 'orange wireframe'}): `
      + `${solvedBy(c.solver, c.backend, c.method)}`,
    `  ${c.functions}`,
    `  ${c.ms_per_step.toFixed(2)} ms/step against ${s.ms_per_step.toFixed(2)}`,
  ];
}

function formatNumber(x) {
  if (x === 0) return '0';
  if (Math.abs(x) >= 1e4 || Math.abs(x) < 1e-2) return x.toExponential(1);
  return String(Number(x.toPrecision(3)));
}

// ---------------------------------------------------------------------------
// The plot. Alone, for the last steps (oldest on the left): the relative
// gradient where each step stopped (blue line, log scale, 1 at the top,
// 1e-8 at the bottom) and the iterations it used (grey bars, up to the
// iteration budget). When comparing, two panels of both simulations (blue:
// the first, orange: the compared one): the mechanical energy (kinetic,
// springs, gravity: Simulation::mechanical_energy) above the lowest either
// reached, log scale, which shows how fast each settles, and the time each
// step took (milliseconds).

const plot = document.getElementById('plot');
const plotContext = plot.getContext('2d');
const PLOT_DECADES = 8;
const PLOT_LEFT = 30;
const PLOT_STEPS = 150; // the history's length (api.rs)

function drawPlot() {
  const s = state.status;
  const height = s && s.compare ? 168 : 96;
  if (plot.height !== height) {
    plot.height = height;
    plot.style.height = `${height}px`;
  }
  plotContext.clearRect(0, 0, plot.width, plot.height);
  if (!s) return;
  plotContext.font = '9px ui-monospace, monospace';
  if (s.compare) drawComparison(s); else drawConvergence(s);
  window.viewer.plotPoints = s.history.length;
}

function drawConvergence(s) {
  const c = plotContext;
  const { width, height } = plot;
  const bottom = height - 12;
  const top = 4;
  const columns = Math.max(1, s.history.length);
  const columnWidth = (width - PLOT_LEFT) / PLOT_STEPS;
  c.fillStyle = '#5d6d7e';
  for (let decade = 0; decade <= PLOT_DECADES; decade += 2) {
    const y = top + (bottom - top) * decade / PLOT_DECADES;
    c.fillText(decade === 0 ? '1' : `1e-${decade}`, 0, y + 3);
    c.fillRect(PLOT_LEFT, y, width - PLOT_LEFT, 0.5);
  }
  c.fillText(`relative gradient (line) · iterations (bars, max ${s.iterations}) · last ${columns} steps`,
    0, height - 1);
  c.fillStyle = 'rgba(127, 140, 141, 0.45)';
  s.history.forEach((record, i) => {
    const h = (bottom - top) * Math.min(1, record.iterations / Math.max(1, s.iterations));
    c.fillRect(PLOT_LEFT + i * columnWidth, bottom - h, Math.max(1, columnWidth - 0.5), h);
  });
  const decades = (record) => (record.relative_gradient === null ? null
    : Math.min(PLOT_DECADES, Math.max(0, -Math.log10(Math.max(record.relative_gradient, 10 ** -PLOT_DECADES)))));
  plotLine(s.history, (record) => decades(record), { top, bottom, low: PLOT_DECADES, high: 0 }, '#3f6fb0');
}

/** Draws `history` as a line: `value(record)` (null: a gap) mapped from
 *  [low, high] to [bottom, top]. */
function plotLine(history, value, { top, bottom, low, high, columns = PLOT_STEPS }, colour) {
  const c = plotContext;
  const columnWidth = (plot.width - PLOT_LEFT) / columns;
  c.strokeStyle = colour;
  c.lineWidth = 1.5;
  c.beginPath();
  let drawing = false;
  history.forEach((record, i) => {
    const v = value(record);
    if (v === null || !Number.isFinite(v)) {
      drawing = false;
      return;
    }
    const y = bottom + (top - bottom) * (v - low) / (high - low || 1);
    const x = PLOT_LEFT + (i + 0.5) * columnWidth;
    if (drawing) c.lineTo(x, y); else c.moveTo(x, y);
    drawing = true;
  });
  c.stroke();
}

/** Both simulations: their mechanical energies, on a log scale above the
 *  lowest either reached (so that how fast each settles shows, whatever
 *  the energy's size), and the time each step took. */
function drawComparison(s) {
  const first = s.history;
  const second = alignedHistory(s);
  const energies = [...first, ...second].map((record) => record.energy).filter(Number.isFinite);
  const lowest = Math.min(...energies);
  const spread = Math.max(...energies) - lowest;
  const floor = lowest - 1e-4 * Math.max(spread, 1e-12);
  const above = (record) => (Number.isFinite(record.energy) ? Math.log10(record.energy - floor) : null);
  const logs = [...first, ...second].map(above).filter((v) => v !== null);
  // At least 30 steps across, so that the first steps of a comparison
  // are not crowded into its left edge.
  const columns = Math.max(30, first.length);
  const energy = {
    top: 12, bottom: 78, low: Math.floor(Math.min(...logs)), high: Math.ceil(Math.max(...logs)), columns,
  };
  const times = [...first, ...second].map((record) => record.ms).filter(Number.isFinite);
  const time = { top: 100, bottom: 152, low: 0, high: Math.max(1, ...times), columns };
  drawPanel(energy, `energy above the lowest (log, 1e${energy.low} to 1e${energy.high})`);
  drawPanel(time, `ms per step (0 to ${time.high.toFixed(0)})`);
  const colours = ['#3f6fb0', `rgb(${LOOK.second.map((c) => 255 * c).join(',')})`];
  plotLine(first, above, energy, colours[0]);
  plotLine(second, above, energy, colours[1]);
  plotLine(first, (record) => record.ms, time, colours[0]);
  plotLine(second, (record) => record.ms, time, colours[1]);
  plotContext.fillStyle = '#5d6d7e';
  plotContext.fillText('blue: this simulation · orange: the compared one', 0, plot.height - 1);
}

/** The compared simulation's history, aligned with the first's by step
 *  (the two step together; the comparison may have started later). */
function alignedHistory(s) {
  const byStep = new Map(s.compare.history.map((record) => [record.step, record]));
  return s.history.map((record) => byStep.get(record.step) || { energy: null, ms: null });
}

/** A panel's frame and title. */
function drawPanel({ top, bottom }, title) {
  const c = plotContext;
  c.fillStyle = '#5d6d7e';
  c.fillText(title, 0, top - 3);
  c.fillRect(PLOT_LEFT, top, plot.width - PLOT_LEFT, 0.5);
  c.fillRect(PLOT_LEFT, bottom, plot.width - PLOT_LEFT, 0.5);
}

// ---------------------------------------------------------------------------
// The controls panel: buttons (the keys' commands, and ■ stop, which
// cancels the step in progress), the scene picker, the solve picker (the
// assignment, the handout's code dense or sparse, the assignment's
// accuracy fast: `--textbook` and `--accuracy` on the command line),
// "compare with" and how the compared simulation is drawn, sliders for k
// (log scale), Δt, the mass scale (log scale) and the iterations, and, for
// experts, the method, the two tolerances, the floor and the start. A
// slider shows its value while it moves and sends set_parameters when let
// go. Every control sends only what it changes: the others are the
// server's values, not read back from controls that would round them.

const controls = {
  play: document.getElementById('play'),
  step: document.getElementById('step'),
  reset: document.getElementById('reset'),
  stop: document.getElementById('stop'),
  wind: document.getElementById('wind'),
  springs: document.getElementById('springs'),
  fit: document.getElementById('fit'),
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

/** Each slider: how its position maps to the parameter and back. */
const SLIDERS = {
  k: { toValue: (x) => 10 ** x, toSlider: Math.log10, show: formatNumber },
  delta_t: { toValue: (x) => x, toSlider: (v) => v, show: (v) => v.toFixed(4) },
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
  return send({ command: 'set_parameters', ...parameters });
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
  return send({ command: 'set_method', ...method });
}

/** A picker's value, `solver` or `solver:backend`, as a command's fields. */
function solverChoice(value) {
  const [solver, backend] = value.split(':');
  return backend ? { solver, backend } : { solver };
}

for (const name of Object.keys(SLIDERS)) {
  const input = document.getElementById(name);
  const output = document.getElementById(`${name}-value`);
  input.addEventListener('input', () => { output.textContent = SLIDERS[name].show(sliderValue(name)); });
  input.addEventListener('change', () => { if (state.status) sendParameters(name); });
}

const BUTTON_COMMANDS = {
  play: 'toggle_animation', step: 'step', reset: 'reset', wind: 'toggle_wind', springs: 'toggle_springs',
  stop: 'cancel',
};
for (const [id, command] of Object.entries(BUTTON_COMMANDS)) {
  controls[id].addEventListener('click', () => send({ command }));
}
controls.fit.addEventListener('click', fitToCloth);
controls.help.addEventListener('click', () => toggleHelp());
controls.scene.addEventListener('change', () => {
  send({ command: 'load_scene', scene: Number(controls.scene.value) });
});
controls.solver.addEventListener('change', () => {
  if (controls.solver.value) send({ command: 'set_solver', ...solverChoice(controls.solver.value) });
});
controls.compare.addEventListener('change', () => {
  const value = controls.compare.value;
  if (!value) {
    send({ command: 'compare', with: null });
    return;
  }
  const { solver, backend } = solverChoice(value);
  send({ command: 'compare', with: solver, ...(backend ? { backend } : {}) });
});
controls.layout.addEventListener('change', () => {
  state.layout = controls.layout.value;
  camera.box = emptyBox(); // frame the pair as it is now drawn
  if (!camera.autoFrame) fitToCloth();
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

/** Shows the status in the controls, except in the one being handled. */
function syncControls() {
  const s = state.status;
  if (!s) return;
  controls.play.textContent = s.animating ? '❚❚ pause' : '▶ play';
  controls.play.classList.toggle('on', s.animating);
  controls.stop.disabled = !s.busy;
  controls.stop.classList.toggle('on', Boolean(s.busy));
  controls.wind.classList.toggle('on', s.wind);
  controls.springs.classList.toggle('on', s.show_springs);
  syncList(controls.scene, s.scenes.map((name, i) => [String(i), name]), String(s.scene_index));
  syncList(controls.method, s.methods.map((name) => [name, name]), s.method);
  const solver = s.solver === 'textbook' ? `textbook:${s.backend}` : (s.solver || '');
  syncPicker(controls.solver, solver);
  const compare = !s.compare ? '' : s.compare.solver === 'textbook' ? `textbook:${s.compare.backend}`
    : (s.compare.solver || '');
  syncPicker(controls.compare, compare);
  controls.layout.disabled = !s.compare || fallback; // the server's images draw it beside
  syncRules(s);
  for (const name of Object.keys(SLIDERS)) {
    const input = document.getElementById(name);
    if (document.activeElement === input && state.sliderHeld) continue;
    input.value = String(SLIDERS[name].toSlider(s[name]));
    document.getElementById(`${name}-value`).textContent = SLIDERS[name].show(s[name]);
  }
}

/** The expert's rules: start, floor and the two tolerances. */
function syncRules(s) {
  if (document.activeElement !== controls.start) controls.start.checked = s.start === 'inertial';
  if (document.activeElement !== controls.atLeastPlain) controls.atLeastPlain.checked = s.at_least_plain !== null;
  for (const [input, name] of [[controls.tolerance, 'tolerance'], [controls.energyTolerance, 'energy_tolerance']]) {
    if (document.activeElement === input) continue;
    input.value = String(toDecades(s[name]));
    document.getElementById(`${name}-value`).textContent = toleranceText(s[name]);
  }
}

/** A select listing `entries` ([value, label]), showing `value`. */
function syncList(select, entries, value) {
  if (select.options.length !== entries.length) {
    select.replaceChildren(...entries.map(([v, label]) => new Option(label, v)));
  }
  if (document.activeElement !== select) select.value = value;
}

/** A fixed picker showing `value` (`''`: the expert's own settings). */
function syncPicker(select, value) {
  if (document.activeElement !== select) select.value = value;
}

window.addEventListener('pointerdown', () => { state.sliderHeld = true; });
window.addEventListener('pointerup', () => { state.sliderHeld = false; });

// ---------------------------------------------------------------------------
// Help overlay: ? or H shows and hides it, Esc hides it.

const helpOverlay = document.getElementById('help-overlay');

function toggleHelp(show = helpOverlay.hidden) {
  helpOverlay.hidden = !show;
}

helpOverlay.addEventListener('click', () => toggleHelp(false));

// ---------------------------------------------------------------------------
// Keys: as the assignment's viewer, plus F (fit), M (next method), ?/H
// (help) and Esc (stop the step in progress, close the help).

const KEY_COMMANDS = {
  ' ': 'step', // pause and advance one step
  a: 'toggle_animation',
  l: 'toggle_springs',
  r: 'reset',
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

window.addEventListener('keydown', (event) => {
  if (event.ctrlKey || event.metaKey || event.altKey) return;
  const target = event.target;
  if (target instanceof HTMLInputElement || target instanceof HTMLSelectElement) return;
  const key = event.key.toLowerCase();
  if (key === '?' || key === 'h') {
    toggleHelp();
  } else if (key === 'escape') {
    toggleHelp(false);
    if (state.status && state.status.busy) send({ command: 'cancel' });
  } else if (key === 'f') {
    fitToCloth();
  } else if (key === 'm') {
    nextMethod();
  } else {
    const command = KEY_COMMANDS[key];
    if (!command) return;
    event.preventDefault();
    if (event.repeat && command !== 'step') return; // holding space keeps stepping
    send({ command });
    return;
  }
  event.preventDefault();
});

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
  camera.autoFrame = false;
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
    state.layout, state.dragTarget && state.dragTarget.join(), state.second !== null].join('|');
}

async function start() {
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
