// The ganzfeld viewer (docs/serve.md). Per model, a row of
//   the indicatrix (lobe) r(j) j, r = f(i, j) / scale, for incidence (theta_i, phi_i); or, with
//   "adjoint", r(k) k with r = f(k, j) for the view j fixed at (theta, phi): the lobe over incident
//   directions; wireframe, solid or transparent, with the normal, the tangent, the mirror direction
//   and i (or j) marked; scale = the row's own maximum or, shared, the largest of both rows
//   the polar plot of f in the plane of incidence (for a model that is not reciprocal also the
//   adjoint f(j, i), dashed, and the largest |f(i, j) - f(j, i)| relative to the largest f)
//   three spheres: a collimated beam (N = H0 (i.n) f), a hemispherical sky (N = N_i g) and a
//   Ganzfeld (N = N_i h): Koenderink & Pont's panel (rasterizer/figure.h), live; each lobe's colour
//   times each light's colour (RGB, as scene files have them).
// Where each number comes from (the page says it under each row):
//   f      the service's GLSL ES 3.00 (/api/glsl?law=f) when the model has one (every analytic
//          model); else (measured data of `serve --data DIR`) the service: /api/fgrid for the lobe
//          and the polar plot, /api/sphere for the beam's sphere
//   g, h   isotropic models: export-glsl's snippets (/api/glsl) sampling the tables of /api/table
//          (format=json, uploaded as R32F with the table's filter), so the page shades as
//          `ganzfeld render` does from the same cache (tests/viewer_test.sh checks it); anisotropic
//          models have no tables: /api/sphere, the cubature per pixel `render` does for them
// Anisotropic lobes are oriented by the sphere's tangent: along the circles of latitude or the
// meridians about the view's up axis (scene/scene.h, TangentRule; latitude by default).
// The URL keeps the state: ?model=SPEC&model_b=SPEC&dir=X,Y,Z (beam)&pole=X,Y,Z&theta=DEG and
// phi=DEG (the lobe's incidence)&lobe=N (its resolution)&adjoint=1&scale=shared&style=wire|solid|
// transparent&along=latitude|longitude&color_a=R,G,B&color_b=R,G,B&beam_rgb=R,G,B&sky_rgb=R,G,B&
// ganzfeld_rgb=R,G,B (colours in [0, 1])&probe=U,V (the numbers at that point of the spheres)&
// table_res=N0xN1xN2,N&table_tol=T (the tables' resolutions and tolerance; default the service's)&
// service_size=N&service_tol=T (the largest side of the spheres the service computes, 256, and the
// tolerance of its cubature per pixel, 1e-4).
// Test mode (?test=1&model=SPEC&light=collimated|sky|ganzfeld&dir=X,Y,Z&size=N[&along=...]): one
// sphere rendered into a float framebuffer, its pixels written as JSON into <pre id="result"> for
// --dump-dom. window.panelReport() says, per row, what each panel holds (tests/viewer_walk.py).
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
// The largest sphere side the service computes by cubature per pixel (serve/field.h,
// kMaxCubatureSphereSide); the page scales its image up to the view.
const kMaxCubatureSide = 96;
const kStyles = ['wire', 'solid', 'transparent'];

function normalize(v) {
  const l = Math.hypot(v[0], v[1], v[2]);
  return [v[0] / l, v[1] / l, v[2] / l];
}
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const deg = (radians) => radians * 180 / Math.PI;
const direction = (thetaDeg, phiDeg) => {
  const t = thetaDeg * Math.PI / 180, p = phiDeg * Math.PI / 180;
  return [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
};

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

/// The tables' resolution and tolerance from the page's URL (table_res=G,H, table_tol=T), as
/// /api/table parameters; empty: the service's defaults (docs/serve.md).
const tableOptions = {res: [], tol: null};
const tableQuery = (law) => {
  const res = tableOptions.res[law === 'g' ? 0 : 1];
  return (res ? `&res=${res}` : '') + (tableOptions.tol ? `&tol=${tableOptions.tol}` : '');
};

/// The shading code and data of one model: f's GLSL (or the service's refusal: no GLSL f), g and
/// h tables + GLSL (or nothing for an anisotropic model: the service computes its spheres).
async function loadModel(spec) {
  const table = (law) => Promise.all([cached(`/api/table?${query(spec, law)}${tableQuery(law)}&format=json`).then(JSON.parse),
                                      cached(`/api/glsl?${query(spec, law)}${tableQuery(law)}`)]);
  const f = cached(`/api/glsl?${query(spec, 'f')}`).then((code) => ({code}), (error) => ({error: error.message}));
  const laws = Promise.all([table('g'), table('h')]).then(
      ([g, h]) => ({g: {table: g[0], code: g[1]}, h: {table: h[0], code: h[1]}}), (error) => ({error: error.message}));
  const [fCode, gh] = await Promise.all([f, laws]);
  // Only these two refusals have another source; any other error (a bad spec, a name not in
  // --data) is the row's error.
  if (gh.error && !/is anisotropic/.test(gh.error)) throw new Error(gh.error);
  if (fCode.error && !/no GLSL form of f/.test(fCode.error)) throw new Error(fCode.error);
  return {spec, f: fCode, g: gh.g || null, h: gh.h || null, anisotropic: Boolean(gh.error)};
}

/// The name of the last function defined in `code` whose parameter list starts with `params` (a
/// regular expression), or null.
function lastFunction(code, params) {
  const pattern = new RegExp(`float (gz_\\w+)\\(${params}`, 'g');
  let name = null;
  for (const m of code.matchAll(pattern)) name = m[1];
  return name;
}
/// lastFunction, which must exist.
function functionName(code, params) {
  const name = lastFunction(code, params);
  if (!name) throw new Error(`no function (${params}...) in the service's GLSL`);
  return name;
}

/// The service's sphere of `law` (f, g, h) lit from `dir`: {value, mask, size} (serve/field.h).
async function serviceSphere(spec, law, dir, size, along) {
  const d = law === 'h' ? '' : `&dir=${dir.map((v) => v.toFixed(6)).join(',')}`;
  const tol = law === 'f' ? '' : `&tol=${state.serviceTol}`;
  const r = JSON.parse(await cached(`/api/sphere?${query(spec, law)}${d}&size=${size}&along=${along}${tol}`));
  return {value: Float32Array.from(r.value), mask: Float32Array.from(r.mask), size: r.width};
}

/// f over the hemisphere from the service (/api/fgrid): as Shading.fGrid.
async function serviceGrid(spec, thetaDeg, phiDeg, nt, adjoint) {
  const r = JSON.parse(await cached(`/api/fgrid?model=${encodeURIComponent(spec)}&theta=${thetaDeg}&phi=${phiDeg}` +
                                    `&res=${nt}&adjoint=${adjoint ? 1 : 0}`));
  const f = Float32Array.from(r.values);
  return {f, max: f.reduce((m, v) => Math.max(m, v), 0), nt, np: 2 * nt};
}

// ---------------------------------------------------------------------------------------------
// WebGL2

const kVertex = `#version 300 es
void main() {  // one triangle covering the viewport
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}`;

/// The fragment shader: the service's f, g and h code, then the three light fields of
/// rasterizer/shading.h on the figure's sphere (u_mode 0, 1, 2), f over the hemisphere for the
/// lobe (u_mode 3), or an image the service computed (u_mode 4: value and mask per pixel).
function fragmentSource(model) {
  const fName = model.f.code ? functionName(model.f.code, 'vec3 i, vec3 j, vec3 n, vec3 t') : null;
  const gName = model.g ? functionName(model.g.code, 'highp sampler3D') : null;
  const hName = model.h ? functionName(model.h.code, 'highp sampler2D table, vec3 j') : null;
  // A mirror delta besides f (he-torrance; export/glsl_f.h, gz_mirror_<spec>): its reflectance
  // rho(j.n) under the Ganzfeld, and under the sky where the mirror direction of j sees the sky,
  // as render adds it (rasterizer/shading.cpp, mirror_term); the tables hold f's laws only.
  const mName = model.f.code ? lastFunction(model.f.code, 'float c\\)') : null;
  const skyMirror = mName ? ` + (dot(2.0 * dot(jc, n) * n - jc, u_light) > 0.0 ? ${mName}(dot(jc, n)) : 0.0)` : '';
  const ganzfeldMirror = mName ? ` + ${mName}(dot(jc, n))` : '';
  return `#version 300 es
precision highp float;
${model.g ? model.g.code : ''}
${model.h ? model.h.code : ''}
${model.f.code || ''}
float F(vec3 i, vec3 j, vec3 n, vec3 t) { return ${fName ? `${fName}(i, j, n, t)` : '0.0'}; }
uniform highp sampler3D u_g;
uniform highp sampler2D u_h;
uniform highp sampler2D u_image;
uniform int u_mode;        // 0 collimated, 1 sky, 2 Ganzfeld, 3 f over the hemisphere, 4 the service's image
uniform vec3 u_light;      // unit: towards the beam's source, or the sky's pole (mode 3: the fixed direction)
uniform float u_intensity; // H0 (collimated) or N (sky, Ganzfeld)
uniform float u_background;
uniform vec3 u_color;      // the lobe's colour times the light's
uniform vec2 u_origin, u_size;
uniform bool u_display;    // sRGB for the screen; else linear radiance and a coverage mask
uniform bool u_latitude;   // the sphere's tangent along the circles of latitude about +y, else its meridians
uniform bool u_adjoint;    // mode 3: f(k, fixed) over k instead of f(fixed, k)
out vec4 color;

const float kPi = 3.14159265358979;
float srgb(float x) {
  x = clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
vec4 shown(float radiance, float mask) {
  if (!u_display) return vec4(radiance, radiance, radiance, mask);
  vec3 c = mask > 0.0 ? radiance * u_color : vec3(radiance);
  return vec4(srgb(c.r), srgb(c.g), srgb(c.b), 1.0);
}
vec3 tangent_at(vec3 n) {
  ${model.f.code ? 'return gz_brush_tangent(n, vec3(0.0, 1.0, 0.0), u_latitude);' : 'return vec3(1.0, 0.0, 0.0);'}
}

void main() {
  vec2 p = gl_FragCoord.xy - u_origin;
  if (u_mode == 3) {  // f at cell centres of (theta, phi) over the hemisphere, n = +z, tangent +x
    float theta = (p.y / u_size.y) * 0.5 * kPi, phi = (p.x / u_size.x) * 2.0 * kPi;
    vec3 k = vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
    vec3 n = vec3(0.0, 0.0, 1.0), t = vec3(1.0, 0.0, 0.0);
    color = vec4(u_adjoint ? F(k, u_light, n, t) : F(u_light, k, n, t), 0.0, 0.0, 1.0);
    return;
  }
  if (u_mode == 4) {  // the service's image, top row first, scaled to the view
    ivec2 size = textureSize(u_image, 0);
    ivec2 q = clamp(ivec2(floor(p / u_size * vec2(size))), ivec2(0), size - 1);
    vec2 value_mask = texelFetch(u_image, ivec2(q.x, size.y - 1 - q.y), 0).rg;
    color = shown(value_mask.y > 0.0 ? u_intensity * value_mask.x : u_background, value_mask.y);
    return;
  }
  // The pixel ray of rasterizer/raster.cpp (pixel_ray): eye (0, 0, ${kEyeZ}), forward -z, up +y.
  float tf = tan(radians(${kFovDeg.toFixed(1)}) * 0.5);
  vec2 uv = (2.0 * p / u_size - 1.0) * tf * vec2(u_size.x / u_size.y, 1.0);
  vec3 eye = vec3(0.0, 0.0, ${kEyeZ.toFixed(1)});
  vec3 d = normalize(vec3(uv, -1.0));
  // Through q, the ray's point nearest the centre: b^2 - c of the textbook formula cancels in
  // float near the silhouette (|eye|^2 = 36 against 1), 1 - q.q does not.
  vec3 q = eye - dot(eye, d) * d;
  float disc = 1.0 - dot(q, q);
  if (disc < 0.0) { color = shown(u_background, 0.0); return; }
  vec3 n = normalize(q - sqrt(disc) * d);
  vec3 j = -d;
  float radiance = 0.0;
  if (u_mode == 0) {  // N = H0 (i.n) f(i, j); nothing in body shadow
    float mi = dot(u_light, n);
    if (mi > 0.0 && dot(j, n) > 0.0) radiance = u_intensity * mi * F(u_light, j, n, tangent_at(n));
  }${gName ? `
  vec3 jc = gz_clamp_to_horizon(j, n);
  if (u_mode == 1) radiance = u_intensity * (${gName}(u_g, u_light, jc, n)${skyMirror});
  if (u_mode == 2) radiance = u_intensity * (${hName}(u_h, jc, n)${ganzfeldMirror});` : ''}
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
/// height n1, depth n0; h a count x 1 2-D texture; one float channel. Its filter is the lookup
/// the table's bound covers (docs/lut-format.md, `filter`): nearest for a texelFetch lookup,
/// linear (OES_texture_float_linear) for one hardware-filtered texture().
function uploadTable(gl, unit, table) {
  const texture = gl.createTexture();
  const target = table.law === 'g' ? gl.TEXTURE_3D : gl.TEXTURE_2D;
  const counts = table.axes.map((a) => a.count);
  const data = new Float32Array(table.value);
  gl.activeTexture(gl.TEXTURE0 + unit);
  gl.bindTexture(target, texture);
  if (table.law === 'g') gl.texImage3D(target, 0, gl.R32F, counts[2], counts[1], counts[0], 0, gl.RED, gl.FLOAT, data);
  else gl.texImage2D(target, 0, gl.R32F, counts[0], 1, 0, gl.RED, gl.FLOAT, data);
  sampling(gl, target, table.filter === 'hardware' ? gl.LINEAR : gl.NEAREST);
  return texture;
}

/// Filtering `filter` (gl.NEAREST or gl.LINEAR) and edges clamped on the bound texture of `target`.
function sampling(gl, target, filter) {
  for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, filter], [gl.TEXTURE_MAG_FILTER, filter],
                        [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE],
                        [gl.TEXTURE_WRAP_R, gl.CLAMP_TO_EDGE]])
    gl.texParameteri(target, k, v);
}

/// The light field of view k: beam H0 = pi N, sky and Ganzfeld N; the background behind it.
const intensityOf = (view) => view === 0 ? Math.PI * kFieldRadiance : kFieldRadiance;
const backgroundOf = (view) => view === 2 ? kFieldRadiance : kBackground;

/// A model's shading on a WebGL2 context: draw() one field into a viewport, fGrid() f over the
/// hemisphere.
class Shading {
  constructor(gl, model) {
    this.gl = gl;
    this.model = model;
    this.program = program(gl, fragmentSource(model));
    gl.useProgram(this.program);
    if (model.g) {
      uploadTable(gl, 0, model.g.table);
      uploadTable(gl, 1, model.h.table);
      gl.uniform1i(this.location('u_g'), 0);
      gl.uniform1i(this.location('u_h'), 1);
    }
    gl.uniform1i(this.location('u_image'), 3);
    this.textures = new WeakMap();  // service image -> its RG32F texture
  }
  location(name) { return this.gl.getUniformLocation(this.program, name); }

  /// Where view k's numbers come from: 'glsl' (f), 'tables' (g, h) or 'service' (/api/sphere).
  source(view) { return view === 0 ? (this.model.f.code ? 'glsl' : 'service') : (this.model.g ? 'tables' : 'service'); }

  /// View `view` (0 collimated, 1 sky, 2 Ganzfeld) into the viewport at (x, y), w x h; from the
  /// service's `image` where source(view) is 'service'. `color` (display only): lobe x light RGB.
  draw(view, light, x, y, w, h, display, {color = [1, 1, 1], image = null, latitude = true} = {}) {
    const gl = this.gl;
    gl.useProgram(this.program);
    gl.viewport(x, y, w, h);
    if (this.source(view) === 'service') {
      if (!image) return false;
      gl.activeTexture(gl.TEXTURE3);
      gl.bindTexture(gl.TEXTURE_2D, this.texture(image));
    }
    gl.uniform1i(this.location('u_mode'), this.source(view) === 'service' ? 4 : view);
    gl.uniform3fv(this.location('u_light'), light);
    gl.uniform1f(this.location('u_intensity'), intensityOf(view));
    gl.uniform1f(this.location('u_background'), backgroundOf(view));
    gl.uniform3fv(this.location('u_color'), color);
    gl.uniform2f(this.location('u_origin'), x, y);
    gl.uniform2f(this.location('u_size'), w, h);
    gl.uniform1i(this.location('u_display'), display ? 1 : 0);
    gl.uniform1i(this.location('u_latitude'), latitude ? 1 : 0);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    return true;
  }

  texture(image) {
    if (!this.textures.has(image)) {
      const gl = this.gl, texture = gl.createTexture(), texels = new Float32Array(2 * image.value.length);
      image.value.forEach((v, k) => { texels[2 * k] = v; texels[2 * k + 1] = image.mask[k]; });
      gl.activeTexture(gl.TEXTURE3);
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RG32F, image.size, image.size, 0, gl.RG, gl.FLOAT, texels);
      sampling(gl, gl.TEXTURE_2D, gl.NEAREST);
      this.textures.set(image, texture);
    }
    return this.textures.get(image);
  }

  /// Linear radiance of view `view` rendered into a float framebuffer, top row first:
  /// {value: Float32Array w*h, mask: 1 sphere, 0.5 near the silhouette, 0 background}.
  readField(view, light, size, options = {}) {
    const pixels = this.offscreen(size, size, () => this.draw(view, light, 0, 0, size, size, false, options));
    const value = new Float32Array(size * size), mask = new Float32Array(size * size);
    for (let y = 0; y < size; ++y)
      for (let x = 0; x < size; ++x) {
        const from = 4 * ((size - 1 - y) * size + x);  // GL rows are bottom first
        value[y * size + x] = pixels[from];
        mask[y * size + x] = pixels[from + 3];
      }
    return {value, mask};
  }

  /// f(fixed, k) (or, adjoint, f(k, fixed)) for k at the centres of an nt x 2 nt grid of
  /// (theta, phi), rows theta, in the local frame (n = +z, tangent +x): {f, max, nt, np}.
  fGrid(fixed, nt, adjoint = false) {
    const np = 2 * nt;
    const pixels = this.offscreen(np, nt, () => {
      const gl = this.gl;
      gl.useProgram(this.program);
      gl.viewport(0, 0, np, nt);
      gl.uniform1i(this.location('u_mode'), 3);
      gl.uniform3fv(this.location('u_light'), fixed);
      gl.uniform1i(this.location('u_adjoint'), adjoint ? 1 : 0);
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
  // Hardware-filtered tables are R32F textures sampled with LINEAR.
  if (!gl.getExtension('OES_texture_float_linear')) throw new Error('no OES_texture_float_linear');
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
  phiLobe: 180,       // its azimuth from the tangent (+x), degrees: 180 = from the left, as the figure
  adjoint: false,     // the lobe over incident directions k, f(k, j), for the view j at (theta, phi)
  sharedScale: false, // one scale for both rows' lobes (their magnitudes compare)
  style: 'wire',      // kStyles
  latitude: true,     // the spheres' tangent: along the circles of latitude about +y, else the meridians
  colors: [[1, 1, 1], [1, 1, 1]],                 // model A's and B's lobe colour (RGB)
  lightColors: [[1, 1, 1], [1, 1, 1], [1, 1, 1]], // the beam's, the sky's and the Ganzfeld's (RGB)
  lobeResolution: 64, // theta_j steps of the lobe (kLobeResolutions)
  lobeYaw: -0.5, lobePitch: 0.35,
  builds: 0,          // rows built so far
  dragging: null,     // the sphere view being dragged (0 beam, 1 sky), or null
  turning: null,      // the last mouse position while the lobe is turned, or null
  rows: [],           // per model: {spec, shading, gl, canvases, grid, adjointGrid, images}
  registry: null,
  data: {files: []},  // /api/data
  serviceSize: 256,   // largest side of a sphere the service computes (service_size=N)
  serviceTol: 1e-4,   // tolerance of its cubature per pixel (service_tol=T)
};

/// The lobe's fixed direction (i, or j in the adjoint view) in the local frame.
const lobeFixed = () => direction(state.thetaLobe, state.phiLobe);
const along = () => (state.latitude ? 'latitude' : 'longitude');

function viewSize() { return Math.max(160, Math.min(320, Math.floor((window.innerWidth - 80) / 5))); }

/// The service's images a row's views need now (beam without a GLSL f; sky and Ganzfeld of an
/// anisotropic model), fetched when the light moves; redraws when they arrive.
function requestImages(row) {
  const shading = row.shading;
  const side = Math.min(row.size, state.serviceSize), cubatureSide = Math.min(side, kMaxCubatureSide);
  const wanted = [[0, 'f', state.light, side], [1, 'g', state.pole, cubatureSide], [2, 'h', [0, 0, 1], cubatureSide]];
  for (const [view, law, dir, size] of wanted) {
    if (shading.source(view) !== 'service') continue;
    const key = `${law}|${dir.join(',')}|${size}|${along()}`;
    if (row.imageKeys[view] === key) continue;
    row.imageKeys[view] = key;
    serviceSphere(row.spec, law, dir, size, along()).then((image) => {
      if (row.imageKeys[view] !== key) return;  // the light moved on meanwhile
      row.images[view] = image;
      drawSpheres(row);
    }, (error) => { row.element.querySelector('.error').textContent = `${kViews[view]}: ${error.message}`; });
  }
}

function drawSpheres(row) {
  const size = row.size;
  for (let k = 0; k < 3; ++k) {
    const color = state.colors[row.index].map((c, m) => c * state.lightColors[k][m]);
    const drawn = row.shading.draw(k, k === 1 ? state.pole : state.light, k * size, 0, size, size, true,
                                   {color, image: row.images[k], latitude: state.latitude});
    if (!drawn) {  // the service's image is on its way: clear the view meanwhile
      const gl = row.gl;
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(k * size, 0, size, size);
      gl.clearColor(0.1, 0.1, 0.1, 1);
      gl.clear(gl.COLOR_BUFFER_BIT);
      gl.disable(gl.SCISSOR_TEST);
    }
  }
}

function redraw() {
  for (const row of state.rows) {
    if (!row.shading) continue;
    requestImages(row);
    drawSpheres(row);
  }
}

/// The scale of a row's lobe: its own largest f, or the largest of every row's (shared).
function lobeScale(row) {
  const own = row.grid ? row.grid.max : 0;
  if (!state.sharedScale) return own;
  return state.rows.reduce((m, r) => Math.max(m, r.grid ? r.grid.max : 0), own);
}

/// The lobe (r(k) k, r = f / scale) turned by yaw and pitch, orthographic; every row's lobe in its
/// colour, wireframe, solid (painter's order, shaded by the facet's slant) or transparent; the
/// normal n (white), the tangent t (green: the local +x axis anisotropic lobes are oriented by),
/// the fixed direction (red: i; cyan: j in the adjoint view) and its mirror direction (yellow).
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
    state.rows.forEach((other) => {
      if (!other.grid || (other !== row && !row.overlay)) return;
      const scale = lobeScale(other);
      if (state.style !== 'wire') drawSolid(ctx, other.grid, scale, project, kLobeColors[other.index], state.style === 'transparent');
      if (state.style !== 'solid') drawWireframe(ctx, other.grid, scale, project, kLobeColors[other.index]);
    });
    const fixed = lobeFixed(), o = project([0, 0, 0]);
    const arrow = (v, color, width = 2) => {
      const tip = project(v.map((x) => 1.3 * x));
      ctx.strokeStyle = color;
      ctx.lineWidth = width;
      ctx.beginPath();
      ctx.moveTo(o[0], o[1]);
      ctx.lineTo(tip[0], tip[1]);
      ctx.stroke();
    };
    arrow([0, 0, 1], '#ddd', 1);
    arrow([1, 0, 0], '#3c3', 1);
    arrow([-fixed[0], -fixed[1], fixed[2]], '#dd3', 1);
    arrow(fixed, state.adjoint ? '#3cd' : '#e33');
    ctx.lineWidth = 1;
  }
}

/// The lobe's point at grid node (a, b): r(k) k with r = f / scale.
function lobePoint(grid, scale, a, b) {
  const theta = (a + 0.5) / grid.nt * Math.PI / 2, phi = (b + 0.5) / grid.np * 2 * Math.PI;
  const r = scale > 0 ? grid.f[a * grid.np + (b % grid.np)] / scale : 0;
  return [r * Math.sin(theta) * Math.cos(phi), r * Math.sin(theta) * Math.sin(phi), r * Math.cos(theta)];
}

/// The grid's theta rings and phi meridians.
function drawWireframe(ctx, grid, scale, project, color) {
  const point = (a, b) => project(lobePoint(grid, scale, a, b));
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

/// The lobe's surface as quads between grid nodes, far ones first, each lit by how squarely it
/// faces the viewer; transparent: at a third of full opacity.
function drawSolid(ctx, grid, scale, project, color, transparent) {
  const step = Math.max(1, grid.nt / 32);  // at most 32 x 64 quads
  const quads = [];
  for (let a = 0; a + step < grid.nt; a += step)
    for (let b = 0; b < grid.np; b += step) {
      const v = [[a, b], [a + step, b], [a + step, b + step], [a, b + step]].map(([x, y]) => lobePoint(grid, scale, x, y));
      const p = v.map(project);
      const e1 = v[2].map((x, k) => x - v[0][k]), e2 = v[3].map((x, k) => x - v[1][k]);
      const nrm = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
      const len = Math.hypot(...nrm);
      if (!(len > 0)) continue;
      const facing = Math.abs(project(nrm.map((x) => x / len))[2] - project([0, 0, 0])[2]);
      quads.push({p, depth: p.reduce((m, q) => m + q[2], 0) / 4, light: 0.35 + 0.65 * Math.min(1, facing)});
    }
  quads.sort((x, y) => y.depth - x.depth);
  const [r, g, b] = [1, 3, 5].map((k) => parseInt(color.slice(k, k + 2), 16));
  ctx.globalAlpha = transparent ? 0.35 : 1;
  for (const q of quads) {
    ctx.fillStyle = `rgb(${Math.round(r * q.light)}, ${Math.round(g * q.light)}, ${Math.round(b * q.light)})`;
    ctx.beginPath();
    q.p.forEach((pt, k) => (k ? ctx.lineTo(pt[0], pt[1]) : ctx.moveTo(pt[0], pt[1])));
    ctx.closePath();
    ctx.fill();
  }
  ctx.globalAlpha = 1;
}

/// f along the plane of incidence: the grid's columns at the boundary of cells nearest to azimuth
/// phi (degrees), the two cells either side averaged.
function planeColumn(grid, a, phi) {
  const b = ((Math.round(phi / 360 * grid.np) % grid.np) + grid.np) % grid.np;
  return 0.5 * (grid.f[a * grid.np + b] + grid.f[a * grid.np + ((b + grid.np - 1) % grid.np)]);
}

/// f in the plane of incidence (towards the source's azimuth on the left, forward on the right),
/// r = f / the lobe's scale, every row's curve in its colour; for a model that is not reciprocal
/// its adjoint dashed, and the largest relative difference written beside.
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
  ctx.strokeStyle = state.adjoint ? '#3cd' : '#e33';
  ctx.beginPath();
  ctx.moveTo(cx, cy);
  ctx.lineTo(cx - R * Math.sin(t), cy - R * Math.cos(t));
  ctx.stroke();
  row.polarPoints = 0;
  state.rows.forEach((other) => {
    if (!other.grid || (other !== row && !row.overlay)) return;
    const scale = lobeScale(other);
    const curve = (grid, dashed) => {
      ctx.strokeStyle = kLobeColors[other.index];
      ctx.setLineDash(dashed ? [4, 3] : []);
      ctx.beginPath();
      const samples = [];
      for (let a = grid.nt - 1; a >= 0; --a) samples.push([a, state.phiLobe, -1]);
      for (let a = 0; a < grid.nt; ++a) samples.push([a, state.phiLobe + 180, 1]);
      samples.forEach(([a, phi, side], k) => {
        const f = planeColumn(grid, a, phi);
        if (other === row && f > 0) row.polarPoints += 1;
        const r = scale > 0 ? f / scale : 0, theta = (a + 0.5) / grid.nt * Math.PI / 2;
        const x = cx + side * R * r * Math.sin(theta), y = cy - R * r * Math.cos(theta);
        k ? ctx.lineTo(x, y) : ctx.moveTo(x, y);
      });
      ctx.stroke();
      ctx.setLineDash([]);
    };
    curve(other.grid, false);
    if (other.reciprocity > kReciprocityNoise) curve(other.adjointGrid, true);
  });
  if (row.reciprocity > kReciprocityNoise) {
    ctx.fillStyle = '#ccc';
    ctx.font = '11px monospace';
    ctx.fillText(`not reciprocal: max|f(i,j)-f(j,i)|/max f = ${row.reciprocity.toPrecision(3)}`, 4, s - 6);
  }
}
/// Below this, f(i, j) and f(j, i) computed in float differ by rounding alone.
const kReciprocityNoise = 1e-4;

/// The lobe's grid and its adjoint (the other argument of f fixed), from the GPU or the service;
/// the largest |f(fixed, k) - f(k, fixed)| over k relative to the largest f.
async function updateLobes() {
  const fixed = lobeFixed(), nt = state.lobeResolution;
  await Promise.all(state.rows.map(async (row) => {
    if (!row.shading) return;
    const grids = row.model.f.code
      ? [row.shading.fGrid(fixed, nt, false), row.shading.fGrid(fixed, nt, true)]
      : await Promise.all([false, true].map((adjoint) => serviceGrid(row.spec, state.thetaLobe, state.phiLobe, nt, adjoint)));
    const [forward, backward] = grids;
    row.grid = state.adjoint ? backward : forward;
    row.adjointGrid = state.adjoint ? forward : backward;
    let difference = 0;
    for (let k = 0; k < forward.f.length; ++k) difference = Math.max(difference, Math.abs(forward.f[k] - backward.f[k]));
    const largest = Math.max(forward.max, backward.max);
    row.reciprocity = largest > 0 ? difference / largest : 0;
  }));
  drawLobes();
  state.rows.forEach((row) => row.polar && drawPolar(row));
}

/// Where a row's panels come from, written under it.
function sourcesText(row) {
  const f = row.model.f.code ? 'f: the service\'s GLSL (/api/glsl)' : 'f: the service (no GLSL f: /api/fgrid for the lobe, /api/sphere for the beam)';
  const gh = row.model.g ? 'g, h: tables (/api/table) sampled by the exported GLSL'
    : `g, h: cubature per pixel on the service (anisotropic: no tables; /api/sphere, tolerance ${state.serviceTol})`;
  return `${f}; ${gh}`;
}

const rgbText = (c) => c.map((x) => Number(x.toFixed(3))).join(',');
const hexOf = (c) => '#' + c.map((x) => Math.round(255 * Math.max(0, Math.min(1, x))).toString(16).padStart(2, '0')).join('');
const rgbOf = (hex) => [1, 3, 5].map((k) => parseInt(hex.slice(k, k + 2), 16) / 255);

/// Builds the row of `spec` (index 0: model A, 1: model B) in `container`.
async function buildRow(container, spec, index) {
  const size = viewSize();
  const element = document.createElement('div');
  element.innerHTML = `<div class="model-title" style="color:${kLobeColors[index]}"></div>
    <div class="row"><canvas class="lobe"></canvas><canvas class="polar"></canvas><canvas class="spheres"></canvas></div>
    <div class="caption"><div style="width:${size}px">${state.adjoint ? 'adjoint: f(k, j) over k, j at' : 'indicatrix r(j) j, i at'}
      θ = <span class="theta-value">${state.thetaLobe}</span>°
      <input type="range" class="theta" min="0" max="89" value="${state.thetaLobe}"><br>
      φ = <span class="phi-value">${state.phiLobe}</span>°
      <input type="range" class="phi" min="0" max="360" value="${state.phiLobe}">
      <select class="resolution" title="lobe resolution: theta x phi steps">${kLobeResolutions.map((n) =>
        `<option value="${n}"${n === state.lobeResolution ? ' selected' : ''}>${n}×${2 * n}</option>`).join('')}</select></div>
      <div style="width:${size}px">polar plot, plane of incidence</div>
      ${kViewTitles.map((t) => `<div style="width:${size}px">${t}</div>`).join('')}</div>
    <div class="sources"></div>
    <div class="error"></div>`;
  container.appendChild(element);
  element.querySelector('.model-title').textContent = (index ? 'B: ' : 'A: ') + spec + `  (colour ${rgbText(state.colors[index])})`;
  const row = {spec, size, element, index, overlay: true, images: [null, null, null], imageKeys: [null, null, null]};
  row.lobe = element.querySelector('.lobe');
  row.polar = element.querySelector('.polar');
  row.spheres = element.querySelector('.spheres');
  row.lobe.width = row.lobe.height = row.polar.width = row.polar.height = size;
  row.spheres.width = 3 * size;
  row.spheres.height = size;
  row.gl = context(row.spheres);
  row.model = await loadModel(spec);
  row.shading = new Shading(row.gl, row.model);
  element.querySelector('.sources').textContent = sourcesText(row);
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
    state.builds += 1;
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
  await updateLobes();
  state.builds += 1;  // tests/viewer_drive.py and viewer_walk.py wait for this after a change
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
  const slider = (name, set) => row.element.querySelector(`.${name}`).addEventListener('input', (e) => {
    set(Number(e.target.value));
    document.querySelectorAll(`.${name}`).forEach((t) => { t.value = e.target.value; });
    document.querySelectorAll(`.${name}-value`).forEach((t) => { t.textContent = e.target.value; });
    updateLobes();
  });
  slider('theta', (v) => { state.thetaLobe = v; });
  slider('phi', (v) => { state.phiLobe = v; });
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

/// What each panel of each row holds, for tests/viewer_walk.py: the lobe's largest f and its
/// non-zero nodes, the polar plot's non-zero samples, and per sphere view its source and how many
/// of its pixels on the sphere are lit (> 0), from a float readback of `size` pixels a side.
window.panelReport = function panelReport(size = 32) {
  return state.rows.map((row) => {
    const views = [0, 1, 2].map((view) => {
      const source = row.shading.source(view);
      const light = view === 1 ? state.pole : state.light;
      let lit = 0, onSphere = 0;
      if (source === 'service') {
        const image = row.images[view];
        if (image) image.value.forEach((v, k) => { onSphere += image.mask[k] > 0; lit += image.mask[k] > 0 && v > 0; });
      } else {
        const field = row.shading.readField(view, light, size, {latitude: state.latitude});
        field.value.forEach((v, k) => { onSphere += field.mask[k] > 0; lit += field.mask[k] > 0 && v > 0; });
      }
      return {view: kViews[view], source, onSphere, lit};
    });
    const nodes = row.grid ? row.grid.f.reduce((n, v) => n + (v > 0 ? 1 : 0), 0) : 0;
    return {spec: row.spec, error: row.element.querySelector('.error').textContent,
            lobe: {max: row.grid ? row.grid.max : 0, nonzero: nodes}, polar: row.polarPoints || 0,
            reciprocity: row.reciprocity, views};
  });
};

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
  // Every model that needs no data file, then the measured files of `serve --data DIR` by name.
  const models = state.registry.models.filter((m) => !m.parameters.some((p) => p.type === 'path' && p.required));
  const dataSpecs = new Set(state.data.files.map((f) => f.spec));
  select.innerHTML = (letter === 'b' ? '<option value="">(none)</option>' : '') +
    models.map((m) => `<option>${m.name}</option>`).join('') +
    state.data.files.map((f) => `<option value="${f.spec}">data: ${f.name} (${f.model})</option>`).join('') +
    '<option value="*">(mixture: type the spec)</option>';
  const showData = () => { if (dataSpecs.has(field.value.trim())) { select.value = field.value.trim(); sliders.innerHTML = ''; } };

  const specFromSliders = () => {
    const model = models.find((m) => m.name === select.value);
    const items = [...sliders.querySelectorAll('[data-name]')].map((input) => `${input.dataset.name}=${input.dataset.value}`);
    return model.name + (items.length ? ':' + items.join(',') : '');
  };
  const buildSliders = (model, values) => {
    sliders.innerHTML = '';
    // An optional parameter (one of alternatives, e.g. ggx's alpha or roughness) only when given.
    for (const param of model.parameters.filter((p) => p.type !== 'path' && (!p.optional || values[p.name] !== undefined))) {
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
    showData();  // a file of --data: its menu entry, no sliders
  };
  select.addEventListener('change', () => {
    const model = models.find((m) => m.name === select.value);
    if (model) { buildSliders(model, {}); field.value = specFromSliders(); } else if (!select.value) field.value = '';
    if (dataSpecs.has(select.value)) { sliders.innerHTML = ''; field.value = select.value; }
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

/// A colour R,G,B of the URL, each in [0, 1]; one line naming the parameter otherwise.
function parseColor(name, text) {
  const v = String(text).split(',').map(Number);
  if (v.length !== 3 || !v.every((x) => Number.isFinite(x) && x >= 0 && x <= 1))
    throw new Error(`${name}=${text} is out of range; allowed: R,G,B, three numbers in [0, 1]`);
  return v;
}

/// The URL's view parameters into `state`; throws one line naming a bad value and what is allowed.
function readViewParameters(params) {
  if (params.get('dir')) state.light = parseVector(params.get('dir'));
  if (params.get('pole')) state.pole = parseVector(params.get('pole'));
  if (kLobeResolutions.includes(Number(params.get('lobe')))) state.lobeResolution = Number(params.get('lobe'));
  if (params.get('theta')) state.thetaLobe = Math.max(0, Math.min(89, Number(params.get('theta')) || 45));
  if (params.has('phi')) {
    const phi = Number(params.get('phi'));
    if (!(Number.isFinite(phi) && phi >= 0 && phi <= 360))
      throw new Error(`phi=${params.get('phi')} is out of range; allowed: an azimuth in [0, 360] degrees`);
    state.phiLobe = phi;
  }
  state.adjoint = params.get('adjoint') === '1';
  state.sharedScale = params.get('scale') === 'shared';
  const style = params.get('style') || 'wire';
  if (!kStyles.includes(style)) throw new Error(`style=${style} is not allowed; allowed: ${kStyles.join(', ')}`);
  state.style = style;
  const tangent = params.get('along') || 'latitude';
  if (tangent !== 'latitude' && tangent !== 'longitude') throw new Error(`along=${tangent} is not allowed; allowed: latitude, longitude`);
  state.latitude = tangent === 'latitude';
  ['color_a', 'color_b'].forEach((name, k) => { if (params.has(name)) state.colors[k] = parseColor(name, params.get(name)); });
  ['beam_rgb', 'sky_rgb', 'ganzfeld_rgb'].forEach((name, k) => {
    if (params.has(name)) state.lightColors[k] = parseColor(name, params.get(name));
  });
  if (params.get('table_res')) tableOptions.res = params.get('table_res').split(',');
  if (params.get('service_size')) state.serviceSize = Math.max(8, Math.min(256, Number(params.get('service_size')) || 256));
  if (params.get('service_tol')) state.serviceTol = Number(params.get('service_tol')) || 1e-4;
  if (params.get('table_tol')) tableOptions.tol = params.get('table_tol');
}

/// The view fieldset: adjoint, shared scale, lobe style, tangent, colours; each change is kept in
/// the URL and redrawn.
function setupViewControls() {
  const byId = (id) => document.getElementById(id);
  const keep = (name, value) => {
    const url = new URL(window.location);
    if (value === null) url.searchParams.delete(name); else url.searchParams.set(name, value);
    window.history.replaceState(null, '', url);
  };
  byId('adjoint').checked = state.adjoint;
  byId('shared-scale').checked = state.sharedScale;
  byId('style').value = state.style;
  byId('along').value = along();
  byId('adjoint').addEventListener('change', (e) => { state.adjoint = e.target.checked; keep('adjoint', state.adjoint ? '1' : null); rebuild(); });
  byId('shared-scale').addEventListener('change', (e) => {
    state.sharedScale = e.target.checked;
    keep('scale', state.sharedScale ? 'shared' : null);
    drawLobes();
    state.rows.forEach((row) => drawPolar(row));
  });
  byId('style').addEventListener('change', (e) => { state.style = e.target.value; keep('style', state.style); drawLobes(); });
  byId('along').addEventListener('change', (e) => { state.latitude = e.target.value === 'latitude'; keep('along', e.target.value); redraw(); });
  const colors = [['color-a', state.colors, 0, 'color_a'], ['color-b', state.colors, 1, 'color_b'],
                  ['beam-rgb', state.lightColors, 0, 'beam_rgb'], ['sky-rgb', state.lightColors, 1, 'sky_rgb'],
                  ['ganzfeld-rgb', state.lightColors, 2, 'ganzfeld_rgb']];
  for (const [id, list, k, name] of colors) {
    byId(id).value = hexOf(list[k]);
    byId(id).addEventListener('input', (e) => { list[k] = rgbOf(e.target.value); keep(name, rgbText(list[k])); redraw(); });
  }
}

// ---------------------------------------------------------------------------------------------
// Test mode: one field of one model into a float framebuffer, written as JSON for --dump-dom;
// with display=1 the view as shown, 8-bit sRGB read back from the canvas.

async function testMode(params) {
  const result = document.getElementById('result');
  try {
    const mode = kViews.indexOf(params.get('light'));
    if (mode < 0) throw new Error(`light=${params.get('light')}: allowed collimated, sky, ganzfeld`);
    const size = Number(params.get('size') || 64);
    const light = mode === 2 ? [0, 1, 0] : parseVector(params.get('dir'));
    readViewParameters(params);
    const canvas = document.createElement('canvas');
    canvas.width = canvas.height = size;
    const gl = context(canvas);
    const model = await loadModel(params.get('model'));
    const shading = new Shading(gl, model);
    const source = shading.source(mode);
    const image = source === 'service' ? await serviceSphere(model.spec, ['f', 'g', 'h'][mode], light, size, along()) : null;
    const options = {image, latitude: state.latitude, color: state.colors[0].map((c, m) => c * state.lightColors[mode][m])};
    const field = shading.readField(mode, light, size, options);
    const out = {webgl2: true, renderer: gl.getParameter(gl.RENDERER), model: model.spec, light: kViews[mode], source, dir: light,
                 filters: [model.g, model.h].map((law) => (law ? law.table.filter : null)),  // the lookups of g, h
                 width: size, height: size, value: Array.from(field.value), mask: Array.from(field.mask)};
    if (params.get('display') === '1') {  // as shown: the canvas's 8-bit sRGB, top row first
      shading.draw(mode, light, 0, 0, size, size, true, options);
      const pixels = new Uint8Array(4 * size * size);
      gl.readPixels(0, 0, size, size, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
      out.srgb = [];
      for (let y = size - 1; y >= 0; --y) for (let x = 0; x < size; ++x) out.srgb.push(pixels[4 * (y * size + x)]);
    }
    result.textContent = JSON.stringify(out);
  } catch (e) {
    result.textContent = JSON.stringify({error: e.message});
  }
}

async function main() {
  const params = new URLSearchParams(window.location.search);
  if (params.get('test')) return testMode(params);
  try {
    readViewParameters(params);
    [state.registry, state.data] = await Promise.all([cached('/api/models').then(JSON.parse), cached('/api/data').then(JSON.parse)]);
  } catch (e) {
    document.getElementById('panels').textContent = e.message;
    document.getElementById('result').textContent = JSON.stringify({error: e.message});
    return;
  }
  document.getElementById('spec-a').value = params.get('model') || 'specular:alpha=8';
  document.getElementById('spec-b').value = params.get('model_b') || '';
  window.addEventListener('mouseup', () => { state.dragging = null; state.turning = null; });
  await Promise.all([setupEditor('a', rebuild), setupEditor('b', rebuild)]);
  setupViewControls();
  await rebuild();
  // probe=U,V: the numbers at (U, V) of model A's sphere views (spherePoint), as if the cursor
  // were there (for screenshots and tests/viewer_test.sh).
  const probe = (params.get('probe') || '').split(',').map(Number);
  const point = probe.length === 2 && probe.every(Number.isFinite) && spherePoint(probe[0], probe[1]);
  if (point && state.rows.length) await writeNumbers(state.rows[0], point);
  await imagesArrived();
  document.getElementById('result').textContent = JSON.stringify({ready: true, rows: state.rows.map((r) => r.spec)});
}

/// Resolves to true when every row has the service's images its views need, to false after 60 s.
async function imagesArrived() {
  for (let waited = 0; waited < 600; ++waited) {
    if (state.rows.every((row) => [0, 1, 2].every((v) => row.shading.source(v) !== 'service' || row.images[v]))) return true;
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
  return false;
}
window.imagesArrived = imagesArrived;

main();
