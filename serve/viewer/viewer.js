// The ganzfeld viewer (docs/serve.md). Per model, a row of
//   the indicatrix (lobe) r(j) j, r = f(i, j) / max f, for incidence theta_i in the plane phi = 180°
//   the polar plot of f in the plane of incidence
//   three spheres: a collimated beam (N = H0 (i.n) f), a hemispherical sky (N = N_i g) and a
//   Ganzfeld (N = N_i h): Koenderink & Pont's panel (rasterizer/figure.h), live.
// The shading is the service's own GLSL ES 3.00: f from /api/glsl?law=f, g and h from /api/glsl
// (export-glsl's snippet) sampling the tables of /api/table (format=json, uploaded as R32F), so the
// page shades exactly as `ganzfeld render` does from the same cache (tests/viewer_test.sh checks it).
// The URL keeps the state: ?model=SPEC&model_b=SPEC&dir=X,Y,Z (beam)&pole=X,Y,Z&theta=DEG (lobe's
// incidence)&lobe=N (its resolution)&probe=U,V (the numbers at that point of the spheres).
// Test mode (?test=1&model=SPEC&light=collimated|sky|ganzfeld&dir=X,Y,Z&size=N): one sphere rendered
// into a float framebuffer, its pixels written as JSON into <pre id="result"> for --dump-dom.
'use strict';

// The figure's scene (rasterizer/figure.h and figure.cpp): every field has radiance
// kFieldRadiance; a collimated beam has H0 = pi kFieldRadiance; the camera looks at a unit
// sphere from (0, 0, 6) along -z, y up, with a 25° vertical field of view.
const kFieldRadiance = 0.8;
const kBackground = 0.1;  // behind the collimated and the sky sphere; a Ganzfeld's is its radiance
const kEyeZ = 6.0;
const kFovDeg = 25.0;
// The beam of the figure: 45° from the viewing direction, from the upper right.
const kBeam = normalize([0.5, 0.5, Math.SQRT1_2]);
// Pixels whose j.n is below this lie within a pixel or two of the silhouette, where a tessellated
// sphere (the CPU's coverage test) and the exact one differ: marked so a comparison skips them.
const kSilhouetteCos = 0.05;
// Sampling of f over the hemisphere for the lobe and the polar plot: theta_j steps (adjustable),
// twice as many in phi.
const kLobeResolutions = [16, 32, 64, 128];
const kLobeColors = ['#4aa3ff', '#ff9f40'];
const kViews = ['collimated', 'sky', 'ganzfeld'];
const kViewTitles = ['collimated beam: H0 (i·n) f', 'hemispherical sky: N g', 'Ganzfeld: N h'];

function normalize(v) {
  const l = Math.hypot(v[0], v[1], v[2]);
  return [v[0] / l, v[1] / l, v[2] / l];
}
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const deg = (radians) => radians * 180 / Math.PI;

// ---------------------------------------------------------------------------------------------
// The service

/// GET url as text; 503 (bake queue full) is retried after Retry-After; other errors throw the
/// service's one-line {"error"}.
async function get(url) {
  for (let attempt = 0; ; ++attempt) {
    const response = await fetch(url);
    const text = await response.text();
    if (response.ok) return text;
    if (response.status === 503 && attempt < 30) {
      const seconds = Number(response.headers.get('Retry-After')) || 1;
      await new Promise((resolve) => setTimeout(resolve, seconds * 1000));
      continue;
    }
    let message = text;
    try { message = JSON.parse(text).error; } catch (e) { /* not JSON: the text itself */ }
    throw new Error(`${response.status} ${url}: ${message}`);
  }
}

const cache = new Map();  // url -> promise of text: tables and shaders are immutable per URL
function cached(url) {
  if (!cache.has(url)) cache.set(url, get(url).catch((e) => { cache.delete(url); throw e; }));
  return cache.get(url);
}

const query = (spec, law) => `model=${encodeURIComponent(spec)}&law=${law}`;

/// The shading code and data of one model: f's GLSL (or its refusal), g and h tables + GLSL.
async function loadModel(spec) {
  const table = (law) => Promise.all([cached(`/api/table?${query(spec, law)}&format=json`).then(JSON.parse),
                                      cached(`/api/glsl?${query(spec, law)}`)]);
  const f = cached(`/api/glsl?${query(spec, 'f')}`).then((code) => ({code}), (error) => ({error: error.message}));
  const [g, h, fCode] = await Promise.all([table('g'), table('h'), f]);
  return {spec, f: fCode, g: {table: g[0], code: g[1]}, h: {table: h[0], code: h[1]}};
}

/// The name of the last function defined in `code` whose parameter list starts with `params`.
function functionName(code, params) {
  const pattern = new RegExp(`float (gz_\\w+)\\(${params}`, 'g');
  let name = null;
  for (const m of code.matchAll(pattern)) name = m[1];
  if (!name) throw new Error(`no function (${params}...) in the service's GLSL`);
  return name;
}

// ---------------------------------------------------------------------------------------------
// WebGL2

const kVertex = `#version 300 es
void main() {  // one triangle covering the viewport
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}`;

/// The fragment shader: the service's f, g and h code, then the three light fields of
/// rasterizer/shading.h on the figure's sphere (u_mode 0, 1, 2) or f over the hemisphere for
/// the lobe (u_mode 3).
function fragmentSource(model) {
  const fName = model.f.code ? functionName(model.f.code, 'vec3 i, vec3 j, vec3 n') : null;
  const gName = functionName(model.g.code, 'highp sampler3D');
  const hName = functionName(model.h.code, 'highp sampler2D table, vec3 j');
  return `#version 300 es
${model.g.code}
${model.h.code}
${model.f.code || ''}
float F(vec3 i, vec3 j, vec3 n) { return ${fName ? `${fName}(i, j, n)` : '0.0'}; }
uniform highp sampler3D u_g;
uniform highp sampler2D u_h;
uniform int u_mode;        // 0 collimated, 1 sky, 2 Ganzfeld, 3 f over the hemisphere
uniform vec3 u_light;      // unit: towards the beam's source, or the sky's pole
uniform float u_intensity; // H0 (collimated) or N (sky, Ganzfeld)
uniform float u_background;
uniform vec2 u_origin, u_size;
uniform bool u_display;    // sRGB for the screen; else linear radiance and a coverage mask
out vec4 color;

const float kPi = 3.14159265358979;
float srgb(float x) {
  x = clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
vec4 shown(float radiance, float mask) {
  return u_display ? vec4(vec3(srgb(radiance)), 1.0) : vec4(radiance, radiance, radiance, mask);
}

void main() {
  vec2 p = gl_FragCoord.xy - u_origin;
  if (u_mode == 3) {  // f(i, j) at cell centres of (theta_j, phi_j), n = +z
    float theta = (p.y / u_size.y) * 0.5 * kPi, phi = (p.x / u_size.x) * 2.0 * kPi;
    vec3 j = vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
    color = vec4(F(u_light, j, vec3(0.0, 0.0, 1.0)), 0.0, 0.0, 1.0);
    return;
  }
  // The pixel ray of rasterizer/raster.cpp (pixel_ray): eye (0, 0, ${kEyeZ}), forward -z, up +y.
  float t = tan(radians(${kFovDeg.toFixed(1)}) * 0.5);
  vec2 uv = (2.0 * p / u_size - 1.0) * t * vec2(u_size.x / u_size.y, 1.0);
  vec3 eye = vec3(0.0, 0.0, ${kEyeZ.toFixed(1)});
  vec3 d = normalize(vec3(uv, -1.0));
  // Through q, the ray's point nearest the centre: b^2 - c of the textbook formula cancels in
  // float near the silhouette (|eye|^2 = 36 against 1), 1 - q.q does not.
  vec3 q = eye - dot(eye, d) * d;
  float disc = 1.0 - dot(q, q);
  if (disc < 0.0) { color = shown(u_background, 0.0); return; }
  vec3 n = normalize(q - sqrt(disc) * d);
  vec3 j = -d;
  vec3 jc = gz_clamp_to_horizon(j, n);
  float radiance = 0.0;
  if (u_mode == 0) {  // N = H0 (i.n) f(i, j); nothing in body shadow
    float mi = dot(u_light, n);
    if (mi > 0.0 && dot(j, n) > 0.0) radiance = u_intensity * mi * F(u_light, j, n);
  } else if (u_mode == 1) {
    radiance = u_intensity * ${gName}(u_g, u_light, jc, n);
  } else {
    radiance = u_intensity * ${hName}(u_h, jc, n);
  }
  color = shown(radiance, dot(j, n) > ${kSilhouetteCos} ? 1.0 : 0.5);
}`;
}

function compile(gl, type, source) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error('shader: ' + gl.getShaderInfoLog(shader));
  return shader;
}

function program(gl, fragment) {
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, kVertex));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, fragment));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error('link: ' + gl.getProgramInfoLog(p));
  return p;
}

/// A table as the exported shader expects it (export/glsl.h): g a 3-D texture of width n2,
/// height n1, depth n0; h a count x 1 2-D texture; one float channel, fetched with texelFetch.
function uploadTable(gl, unit, table) {
  const texture = gl.createTexture();
  const target = table.law === 'g' ? gl.TEXTURE_3D : gl.TEXTURE_2D;
  const counts = table.axes.map((a) => a.count);
  const data = new Float32Array(table.value);
  gl.activeTexture(gl.TEXTURE0 + unit);
  gl.bindTexture(target, texture);
  if (table.law === 'g') gl.texImage3D(target, 0, gl.R32F, counts[2], counts[1], counts[0], 0, gl.RED, gl.FLOAT, data);
  else gl.texImage2D(target, 0, gl.R32F, counts[0], 1, 0, gl.RED, gl.FLOAT, data);
  for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
                        [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]])
    gl.texParameteri(target, k, v);
  return texture;
}

/// A model's shading on a WebGL2 context: draw() one field into a viewport, fGrid() f over the
/// hemisphere.
class Shading {
  constructor(gl, model) {
    this.gl = gl;
    this.program = program(gl, fragmentSource(model));
    uploadTable(gl, 0, model.g.table);
    uploadTable(gl, 1, model.h.table);
    gl.useProgram(this.program);
    gl.uniform1i(this.location('u_g'), 0);
    gl.uniform1i(this.location('u_h'), 1);
  }
  location(name) { return this.gl.getUniformLocation(this.program, name); }

  /// Field `mode` (0 collimated, 1 sky, 2 Ganzfeld) into the viewport at (x, y), w x h.
  draw(mode, light, x, y, w, h, display) {
    const gl = this.gl;
    const intensity = mode === 0 ? Math.PI * kFieldRadiance : kFieldRadiance;
    gl.useProgram(this.program);
    gl.viewport(x, y, w, h);
    gl.uniform1i(this.location('u_mode'), mode);
    gl.uniform3fv(this.location('u_light'), light);
    gl.uniform1f(this.location('u_intensity'), intensity);
    gl.uniform1f(this.location('u_background'), mode === 2 ? kFieldRadiance : kBackground);
    gl.uniform2f(this.location('u_origin'), x, y);
    gl.uniform2f(this.location('u_size'), w, h);
    gl.uniform1i(this.location('u_display'), display ? 1 : 0);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  /// Linear radiance of field `mode` rendered into a float framebuffer, top row first:
  /// {value: Float32Array w*h, mask: 1 sphere, 0.5 near the silhouette, 0 background}.
  readField(mode, light, size) {
    const pixels = this.offscreen(size, size, () => this.draw(mode, light, 0, 0, size, size, false));
    const value = new Float32Array(size * size), mask = new Float32Array(size * size);
    for (let y = 0; y < size; ++y)
      for (let x = 0; x < size; ++x) {
        const from = 4 * ((size - 1 - y) * size + x);  // GL rows are bottom first
        value[y * size + x] = pixels[from];
        mask[y * size + x] = pixels[from + 3];
      }
    return {value, mask};
  }

  /// f(i, j, +z) for j at the centres of an nt x 2 nt grid of (theta_j, phi_j), rows theta_j:
  /// {f, max, nt, np}.
  fGrid(i, nt) {
    const np = 2 * nt;
    const pixels = this.offscreen(np, nt, () => {
      const gl = this.gl;
      gl.useProgram(this.program);
      gl.viewport(0, 0, np, nt);
      gl.uniform1i(this.location('u_mode'), 3);
      gl.uniform3fv(this.location('u_light'), i);
      gl.uniform2f(this.location('u_origin'), 0, 0);
      gl.uniform2f(this.location('u_size'), np, nt);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    });
    const f = new Float32Array(nt * np);
    for (let k = 0; k < f.length; ++k) f[k] = pixels[4 * k];
    return {f, max: f.reduce((m, v) => Math.max(m, v), 0), nt, np};
  }

  /// Runs draw() into an RGBA32F framebuffer and reads it back as floats (not the 8-bit canvas).
  offscreen(w, h, draw) {
    const gl = this.gl;
    const texture = gl.createTexture();
    gl.activeTexture(gl.TEXTURE2);
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, null);
    const fbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE)
      throw new Error('no float framebuffer (EXT_color_buffer_float)');
    draw();
    const pixels = new Float32Array(4 * w * h);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, pixels);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.deleteFramebuffer(fbo);
    gl.deleteTexture(texture);
    return pixels;
  }
}

function context(canvas) {
  const gl = canvas.getContext('webgl2', {antialias: false, preserveDrawingBuffer: true});
  if (!gl) throw new Error('no WebGL2 context');
  if (!gl.getExtension('EXT_color_buffer_float')) throw new Error('no EXT_color_buffer_float');
  return gl;
}

// ---------------------------------------------------------------------------------------------
// Geometry shared by drawing and picking

/// The unit normal and j of the figure's sphere at (u, v) of its view, in [0, 1] from the top
/// left (pixel x's centre: u = (x + 0.5) / size), or null off the sphere: rasterizer/raster.cpp's
/// pixel_ray and the exact sphere.
function spherePoint(u, v) {
  const t = Math.tan(kFovDeg * Math.PI / 360);
  const d = normalize([(2 * u - 1) * t, (1 - 2 * v) * t, -1]);
  const eye = [0, 0, kEyeZ];
  const q = eye.map((e, k) => e - dot(eye, d) * d[k]);  // as the shader
  const disc = 1 - dot(q, q);
  if (disc < 0) return null;
  return {n: normalize(q.map((v, k) => v - Math.sqrt(disc) * d[k])), j: [-d[0], -d[1], -d[2]]};
}

/// Angle in degrees between the tangential parts of a and b at n (0 when either is along n).
function relativeAzimuth(a, b, n) {
  const ta = a.map((v, k) => v - dot(a, n) * n[k]), tb = b.map((v, k) => v - dot(b, n) * n[k]);
  const la = Math.hypot(...ta), lb = Math.hypot(...tb);
  if (la === 0 || lb === 0) return 0;
  return deg(Math.acos(Math.max(-1, Math.min(1, dot(ta, tb) / (la * lb)))));
}

// ---------------------------------------------------------------------------------------------
// The interactive page

const state = {
  light: kBeam,       // towards the beam's source
  pole: [0, 1, 0],    // the sky's pole
  thetaLobe: 45,      // incidence of the lobe and the polar plot, degrees (K&P's 45°)
  lobeResolution: 64, // theta_j steps of the lobe (kLobeResolutions)
  lobeYaw: -0.5, lobePitch: 0.35,
  builds: 0,          // rows built so far
  dragging: null,     // the sphere view being dragged (0 beam, 1 sky), or null
  turning: null,      // the last mouse position while the lobe is turned, or null
  rows: [],           // per model: {spec, shading, gl, canvases, grid}
  registry: null,
};

/// i of the lobe: theta from the normal, from the left (azimuth 180°), as the figure draws it.
const lobeIncidence = () => {
  const t = state.thetaLobe * Math.PI / 180;
  return [-Math.sin(t), 0, Math.cos(t)];
};

function viewSize() { return Math.max(160, Math.min(320, Math.floor((window.innerWidth - 80) / 5))); }

function drawSpheres(row) {
  const size = row.size;
  for (let k = 0; k < 3; ++k)
    row.shading.draw(k, k === 1 ? state.pole : state.light, k * size, 0, size, size, true);
}

/// The lobe as a wireframe, turned by yaw and pitch, orthographic; every row's lobe in its colour.
function drawLobes() {
  for (const row of state.rows) {
    if (!row.lobe) continue;
    const ctx = row.lobe.getContext('2d');
    const s = row.lobe.width;
    ctx.fillStyle = '#1a1a1a';
    ctx.fillRect(0, 0, s, s);
    const cy = Math.cos(state.lobeYaw), sy = Math.sin(state.lobeYaw);
    const cp = Math.cos(state.lobePitch), sp = Math.sin(state.lobePitch);
    const project = (v) => {  // local frame (n = z) to screen: z up, turn about z, tilt about x
      const x = cy * v[0] - sy * v[1], y = sy * v[0] + cy * v[1];
      const depth = cp * y - sp * v[2], up = sp * y + cp * v[2];
      return [s / 2 + 0.38 * s * x, 0.72 * s - 0.38 * s * up, depth];
    };
    ctx.strokeStyle = '#666';
    ctx.beginPath();
    for (let k = 0; k <= 64; ++k) {
      const a = 2 * Math.PI * k / 64, p = project([Math.cos(a), Math.sin(a), 0]);
      k ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1]);
    }
    ctx.stroke();
    state.rows.forEach((other, index) => {
      if (!other.grid || (other !== row && !row.overlay)) return;
      drawWireframe(ctx, other.grid, project, kLobeColors[index]);
    });
    const i = lobeIncidence(), o = project([0, 0, 0]), tip = project(i.map((v) => 1.3 * v));
    ctx.strokeStyle = '#e33';
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(o[0], o[1]);
    ctx.lineTo(tip[0], tip[1]);
    ctx.stroke();
    ctx.lineWidth = 1;
  }
}

/// r(j) j with r = f / max f on the grid's theta rings and phi meridians.
function drawWireframe(ctx, grid, project, color) {
  const point = (a, b) => {
    const theta = (a + 0.5) / grid.nt * Math.PI / 2, phi = (b + 0.5) / grid.np * 2 * Math.PI;
    const r = grid.max > 0 ? grid.f[a * grid.np + (b % grid.np)] / grid.max : 0;
    return project([r * Math.sin(theta) * Math.cos(phi), r * Math.sin(theta) * Math.sin(phi), r * Math.cos(theta)]);
  };
  ctx.strokeStyle = color;
  ctx.beginPath();
  for (let a = 0; a < grid.nt; a += Math.max(1, grid.nt / 16))
    for (let b = 0; b <= grid.np; ++b) {
      const p = point(a, b);
      b ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1]);
    }
  for (let b = 0; b < grid.np; b += Math.max(1, grid.np / 16))
    for (let a = 0; a < grid.nt; ++a) {
      const p = point(a, b);
      a ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1]);
    }
  ctx.stroke();
}

/// f in the plane of incidence (phi = 0: forward, right; phi = 180°: towards the source, left),
/// r = f / max f over the hemisphere, every row's curve in its colour.
function drawPolar(row) {
  const ctx = row.polar.getContext('2d');
  const s = row.polar.width, cx = s / 2, cy = 0.8 * s, R = 0.7 * s / 2 * 1.25;
  ctx.fillStyle = '#1a1a1a';
  ctx.fillRect(0, 0, s, s);
  ctx.strokeStyle = '#555';
  for (const r of [0.25, 0.5, 0.75, 1]) {
    ctx.beginPath();
    ctx.arc(cx, cy, r * R, Math.PI, 2 * Math.PI);
    ctx.stroke();
  }
  ctx.beginPath();
  ctx.moveTo(cx - R, cy);
  ctx.lineTo(cx + R, cy);
  ctx.stroke();
  const t = state.thetaLobe * Math.PI / 180;
  ctx.strokeStyle = '#e33';
  ctx.beginPath();
  ctx.moveTo(cx, cy);
  ctx.lineTo(cx - R * Math.sin(t), cy - R * Math.cos(t));
  ctx.stroke();
  state.rows.forEach((other, index) => {
    if (!other.grid || (other !== row && !row.overlay)) return;
    ctx.strokeStyle = kLobeColors[index];
    ctx.beginPath();
    // phi = 180° (column np/2) from the horizon to the normal, then phi = 0 back down.
    const {nt, np} = other.grid, half = np / 2;
    const samples = [];
    for (let a = nt - 1; a >= 0; --a) samples.push([a, half, -1]);
    for (let a = 0; a < nt; ++a) samples.push([a, 0, 1]);
    samples.forEach(([a, b, side], k) => {
      // columns b and b-1 straddle the plane (cell centres at (b + 0.5)/np): average them
      const f = 0.5 * (other.grid.f[a * np + b] + other.grid.f[a * np + ((b + np - 1) % np)]);
      const r = other.grid.max > 0 ? f / other.grid.max : 0, theta = (a + 0.5) / nt * Math.PI / 2;
      const x = cx + side * R * r * Math.sin(theta), y = cy - R * r * Math.cos(theta);
      k ? ctx.lineTo(x, y) : ctx.moveTo(x, y);
    });
    ctx.stroke();
  });
}

function updateLobes() {
  for (const row of state.rows) {
    if (!row.shading || !row.model.f.code) { row.grid = null; continue; }
    row.grid = row.shading.fGrid(lobeIncidence(), state.lobeResolution);
  }
  drawLobes();
  state.rows.forEach((row) => row.polar && drawPolar(row));
}

function redraw() {
  for (const row of state.rows) if (row.shading) drawSpheres(row);
}

/// Builds the row of `spec` (index 0: model A, 1: model B) in `container`.
async function buildRow(container, spec, index) {
  const size = viewSize();
  const element = document.createElement('div');
  element.innerHTML = `<div class="model-title" style="color:${kLobeColors[index]}"></div>
    <div class="row"><canvas class="lobe"></canvas><canvas class="polar"></canvas><canvas class="spheres"></canvas></div>
    <div class="caption"><div style="width:${size}px">indicatrix r(j) j, θi = <span class="theta-value">${state.thetaLobe}</span>°
      <input type="range" class="theta" min="0" max="89" value="${state.thetaLobe}">
      <select class="resolution" title="lobe resolution: theta x phi steps">${kLobeResolutions.map((n) =>
        `<option value="${n}"${n === state.lobeResolution ? ' selected' : ''}>${n}×${2 * n}</option>`).join('')}</select></div>
      <div style="width:${size}px">polar plot, plane of incidence</div>
      ${kViewTitles.map((t) => `<div style="width:${size}px">${t}</div>`).join('')}</div>
    <div class="error"></div>`;
  container.appendChild(element);
  element.querySelector('.model-title').textContent = (index ? 'B: ' : 'A: ') + spec;
  const row = {spec, size, element, overlay: true};
  row.lobe = element.querySelector('.lobe');
  row.polar = element.querySelector('.polar');
  row.spheres = element.querySelector('.spheres');
  row.lobe.width = row.lobe.height = row.polar.width = row.polar.height = size;
  row.spheres.width = 3 * size;
  row.spheres.height = size;
  row.gl = context(row.spheres);
  row.model = await loadModel(spec);
  row.shading = new Shading(row.gl, row.model);
  if (row.model.f.error) element.querySelector('.error').textContent = 'f (lobe, beam): ' + row.model.f.error;
  attachRowEvents(row);
  return row;
}

async function rebuild() {
  const container = document.getElementById('panels');
  const specs = [document.getElementById('spec-a').value.trim(), document.getElementById('spec-b').value.trim()];
  const generation = (state.generation = (state.generation || 0) + 1);
  const rows = [];
  const staging = document.createElement('div');
  try {
    for (let k = 0; k < 2; ++k) if (specs[k]) rows.push(await buildRow(staging, specs[k], k));
  } catch (e) {
    if (generation !== state.generation) return;
    container.innerHTML = '';
    const message = document.createElement('div');
    message.className = 'error';
    message.textContent = e.message;
    container.appendChild(message);
    return;
  }
  if (generation !== state.generation) return;  // a newer request superseded this one
  container.replaceChildren(...staging.children);
  // Free the replaced rows' contexts now (browsers keep only a few WebGL contexts alive).
  for (const old of state.rows) old.gl.getExtension('WEBGL_lose_context')?.loseContext();
  state.rows = rows;
  const url = new URL(window.location);
  url.searchParams.set('model', specs[0]);
  if (specs[1]) url.searchParams.set('model_b', specs[1]); else url.searchParams.delete('model_b');
  window.history.replaceState(null, '', url);
  redraw();
  updateLobes();
  state.builds += 1;  // tests/viewer_drive.py waits for this after dragging a slider
}

/// Which sphere view and which point of it a mouse event is over, or null.
function pick(row, event) {
  const rect = row.spheres.getBoundingClientRect();
  const x = (event.clientX - rect.left) * row.spheres.width / rect.width;
  const y = (event.clientY - rect.top) * row.spheres.height / rect.height;
  const view = Math.floor(x / row.size);
  const point = spherePoint((x - view * row.size) / row.size, y / row.size);
  return point && view >= 0 && view < 3 ? {view, ...point} : null;
}

function attachRowEvents(row) {
  row.spheres.addEventListener('mousedown', (e) => {
    const p = pick(row, e);
    if (p && p.view < 2) state.dragging = p.view;
    move(e);
  });
  const move = (e) => {
    const p = pick(row, e);
    if (!p) return;
    if (state.dragging === 0) state.light = p.n;  // the beam comes from the normal under the cursor
    if (state.dragging === 1) state.pole = p.n;
    if (state.dragging !== null) redraw();
    showNumbers(row, p);
  };
  row.spheres.addEventListener('mousemove', move);
  row.element.querySelector('.theta').addEventListener('input', (e) => {
    state.thetaLobe = Number(e.target.value);
    document.querySelectorAll('.theta').forEach((t) => { t.value = state.thetaLobe; });
    document.querySelectorAll('.theta-value').forEach((t) => { t.textContent = state.thetaLobe; });
    updateLobes();
  });
  row.element.querySelector('.resolution').addEventListener('change', (e) => {
    state.lobeResolution = Number(e.target.value);
    document.querySelectorAll('.resolution').forEach((r) => { r.value = e.target.value; });
    updateLobes();
  });
  row.lobe.addEventListener('mousedown', (e) => { state.turning = [e.clientX, e.clientY]; });
  row.lobe.addEventListener('mousemove', (e) => {
    const turning = state.turning;
    if (!turning) return;
    state.lobeYaw += (e.clientX - turning[0]) * 0.01;
    state.lobePitch = Math.max(-1.5, Math.min(1.5, state.lobePitch + (e.clientY - turning[1]) * 0.01));
    state.turning = [e.clientX, e.clientY];
    drawLobes();
  });
}

/// f, g, h, a, r at the point under the cursor from /api/eval, each with its error estimate.
let numbersTimer = null;
function showNumbers(row, p) {
  clearTimeout(numbersTimer);
  numbersTimer = setTimeout(() => writeNumbers(row, p), 120);
}

async function writeNumbers(row, p) {
  const thetaJ = deg(Math.acos(Math.min(1, dot(p.j, p.n))));
  const thetaBeam = deg(Math.acos(Math.max(-1, Math.min(1, dot(state.light, p.n)))));
  const thetaPole = deg(Math.acos(Math.max(-1, Math.min(1, dot(state.pole, p.n)))));
  const fixed = (x) => x.toFixed(2);
  const phiBeam = relativeAzimuth(state.light, p.j, p.n), phiPole = relativeAzimuth(state.pole, p.j, p.n);
  const asks = [
    ['f', thetaBeam <= 90 ? `&theta_i=${fixed(thetaBeam)}&theta_j=${fixed(thetaJ)}&phi=${fixed(phiBeam)}` : null,
     `θi ${fixed(thetaBeam)}° (beam), θj ${fixed(thetaJ)}°, φ ${fixed(phiBeam)}°`],
    ['g', `&theta_i=${fixed(thetaPole)}&theta_j=${fixed(thetaJ)}&phi=${fixed(phiPole)}`,
     `θi ${fixed(thetaPole)}° (pole), θj ${fixed(thetaJ)}°, φ ${fixed(phiPole)}°`],
    ['h', `&theta_j=${fixed(thetaJ)}`, `θj ${fixed(thetaJ)}°`],
    ['a', thetaBeam <= 90 ? `&theta_i=${fixed(thetaBeam)}` : null, `θi ${fixed(thetaBeam)}° (beam)`],
    ['r', '', ''],
  ];
  const lines = await Promise.all(asks.map(async ([law, angles, where]) => {
    if (angles === null) return `${law}  (beam below the horizon)`;
    try {
      const e = JSON.parse(await cached(`/api/eval?${query(row.spec, law)}${angles}&tol=1e-6`));
      return `${law} = ${e.value.toPrecision(6)} ± ${e.error.toExponential(1)}${e.converged ? '' : ' (not converged)'}  ${where}`;
    } catch (error) {
      return `${law}: ${error.message}`;
    }
  }));
  document.getElementById('numbers').textContent = `${row.spec}\n${lines.join('\n')}`;
}

// ---------------------------------------------------------------------------------------------
// Model menus and sliders, from /api/models

/// A slider's value <-> position: logarithmic over ranges spanning more than two decades.
function sliderScale(param) {
  let min = Number.isFinite(param.min) ? param.min : -10, max = Number.isFinite(param.max) ? param.max : null;
  if (max === null) max = Math.max(10 * Math.abs(param.default), min + 10);
  if (param.min_exclusive) min = min > 0 ? min * 1.001 : min + 1e-3 * (max - min);
  const log = min > 0 && max / min > 100;
  return {
    min, max, integer: param.type === 'integer',
    value: (t) => log ? Math.exp(Math.log(min) + t * (Math.log(max) - Math.log(min))) : min + t * (max - min),
    position: (v) => log ? (Math.log(v) - Math.log(min)) / (Math.log(max) - Math.log(min)) : (v - min) / (max - min),
  };
}

const formatValue = (v, integer) => integer ? String(Math.round(v)) : String(Number(v.toPrecision(4)));

/// A single model's spec as the service parses it (/api/spec): {name, values} with the values the
/// spec gives, or null (a mixture, or a spec the service refuses).
async function parseSpec(spec) {
  if (!spec.trim()) return null;
  try {
    const terms = JSON.parse(await cached(`/api/spec?model=${encodeURIComponent(spec)}`)).terms;
    return terms.length === 1 ? {name: terms[0].model, values: terms[0].parameters} : null;
  } catch (e) {
    return null;
  }
}

/// The menu and sliders of one spec field; the sliders rewrite the spec, the spec (typed or a
/// mixture) sets the menu and the sliders where it can. Resolves when they show the field's spec.
function setupEditor(letter, onChange) {
  const select = document.getElementById(`model-${letter}`);
  const sliders = document.getElementById(`sliders-${letter}`);
  const field = document.getElementById(`spec-${letter}`);
  const models = state.registry.models.filter((m) => m.isotropic && !m.parameters.some((p) => p.type === 'path' && p.required));
  select.innerHTML = (letter === 'b' ? '<option value="">(none)</option>' : '') +
    models.map((m) => `<option>${m.name}</option>`).join('') + '<option value="*">(mixture: type the spec)</option>';

  const specFromSliders = () => {
    const model = models.find((m) => m.name === select.value);
    const items = [...sliders.querySelectorAll('[data-name]')].map((input) => `${input.dataset.name}=${input.dataset.value}`);
    return model.name + (items.length ? ':' + items.join(',') : '');
  };
  const buildSliders = (model, values) => {
    sliders.innerHTML = '';
    for (const param of model.parameters.filter((p) => p.type !== 'path')) {
      const div = document.createElement('div');
      div.className = 'slider';
      const given = values[param.name];
      if (param.type === 'choice') {
        div.innerHTML = `<label>${param.name}</label><select data-name="${param.name}">${param.choices.map((c) => `<option>${c}</option>`).join('')}</select><span></span>`;
        const input = div.querySelector('select');
        input.value = given ?? param.default;
        input.dataset.value = input.value;
        input.addEventListener('change', () => { input.dataset.value = input.value; field.value = specFromSliders(); onChange(); });
      } else {
        const scale = sliderScale(param);
        div.innerHTML = `<label title="${param.meaning}">${param.name}</label><input type="range" min="0" max="1000" data-name="${param.name}"><span></span>`;
        const input = div.querySelector('input'), label = div.querySelector('span');
        const set = (v) => { input.dataset.value = formatValue(v, scale.integer); label.textContent = input.dataset.value; };
        const start = given !== undefined ? Number(given) : param.default;
        set(start);
        input.value = String(Math.round(1000 * Math.max(0, Math.min(1, scale.position(start)))));
        input.title = param.meaning;
        input.addEventListener('input', () => set(scale.value(input.value / 1000)));
        input.addEventListener('change', () => { field.value = specFromSliders(); onChange(); });
      }
      sliders.appendChild(div);
    }
  };
  const fromSpec = async () => {
    const parsed = await parseSpec(field.value);
    const model = parsed && models.find((m) => m.name === parsed.name);
    select.value = model ? model.name : (field.value.trim() ? '*' : '');
    if (model) buildSliders(model, parsed.values); else sliders.innerHTML = '';
  };
  select.addEventListener('change', () => {
    const model = models.find((m) => m.name === select.value);
    if (model) { buildSliders(model, {}); field.value = specFromSliders(); } else if (!select.value) field.value = '';
    onChange();
  });
  field.addEventListener('change', () => { fromSpec(); onChange(); });
  return fromSpec();
}

function parseVector(text) {
  const v = (text || '').split(',').map(Number);
  if (v.length !== 3 || !v.every(Number.isFinite) || Math.hypot(...v) === 0) throw new Error(`dir=${text}: expected X,Y,Z`);
  return normalize(v);
}

// ---------------------------------------------------------------------------------------------
// Test mode: one field of one model into a float framebuffer, written as JSON for --dump-dom

async function testMode(params) {
  const result = document.getElementById('result');
  try {
    const mode = kViews.indexOf(params.get('light'));
    if (mode < 0) throw new Error(`light=${params.get('light')}: allowed collimated, sky, ganzfeld`);
    const size = Number(params.get('size') || 64);
    const light = mode === 2 ? [0, 1, 0] : parseVector(params.get('dir'));
    const canvas = document.createElement('canvas');
    const gl = context(canvas);
    const model = await loadModel(params.get('model'));
    if (mode === 0 && model.f.error) throw new Error(model.f.error);
    const field = new Shading(gl, model).readField(mode, light, size);
    result.textContent = JSON.stringify({
      webgl2: true, renderer: gl.getParameter(gl.RENDERER), model: model.spec, light: kViews[mode], dir: light,
      width: size, height: size, value: Array.from(field.value), mask: Array.from(field.mask)});
  } catch (e) {
    result.textContent = JSON.stringify({error: e.message});
  }
}

async function main() {
  const params = new URLSearchParams(window.location.search);
  if (params.get('test')) return testMode(params);
  if (params.get('dir')) state.light = parseVector(params.get('dir'));
  if (params.get('pole')) state.pole = parseVector(params.get('pole'));
  if (kLobeResolutions.includes(Number(params.get('lobe')))) state.lobeResolution = Number(params.get('lobe'));
  if (params.get('theta')) state.thetaLobe = Math.max(0, Math.min(89, Number(params.get('theta')) || 45));
  try {
    state.registry = JSON.parse(await cached('/api/models'));
  } catch (e) {
    document.getElementById('panels').textContent = e.message;
    return;
  }
  document.getElementById('spec-a').value = params.get('model') || 'specular:alpha=8';
  document.getElementById('spec-b').value = params.get('model_b') || '';
  window.addEventListener('mouseup', () => { state.dragging = null; state.turning = null; });
  await Promise.all([setupEditor('a', rebuild), setupEditor('b', rebuild)]);
  await rebuild();
  // probe=U,V: the numbers at (U, V) of model A's sphere views (spherePoint), as if the cursor
  // were there (for screenshots and tests/viewer_test.sh).
  const probe = (params.get('probe') || '').split(',').map(Number);
  const point = probe.length === 2 && probe.every(Number.isFinite) && spherePoint(probe[0], probe[1]);
  if (point && state.rows.length) await writeNumbers(state.rows[0], point);
  document.getElementById('result').textContent = JSON.stringify({ready: true, rows: state.rows.map((r) => r.spec)});
}

main();
