// The module's tables looked up on the GPU at seeded random points, for tests/threejs_test.sh:
// every roughness set of ?tables=MANIFEST is read by the module (GanzfeldTables, tableTexture) and
// its GLSL chunk (ganzfeldParsChunk: the four exported functions and their Schlick combinations)
// is evaluated per point into an RGBA32F target: (sky law of f0 = 0, of f0 = 1, Ganzfeld law of
// f0 = 0, of f0 = 1), from gz_three_sky and gz_three_ganzfeld with f0 = (0, 1, 0) and f90 = 1.
// The points are directions in random frames; the page also writes them in the local frame
// (n = +z), where tests/threejs_compare.cpp looks the same tables up with tables::sample.
//   ?tables=URL&points=N&seed=S
import * as THREE from 'three';
import {GanzfeldTables, ganzfeldParsChunk, tableTexture} from 'ganzfeld-three';

const params = new URLSearchParams(location.search);
const report = (object) => { document.getElementById('result').textContent = JSON.stringify(object); };

/// mulberry32: a small seeded generator, so a failing point can be reproduced.
function generator(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

/// N points: local i (i.n uniform in [-1, 1], any azimuth), j (j.n uniform in [0, 1]), and a random
/// rotation taking the local frame to the world one.
function points(count, random) {
  const out = [];
  for (let k = 0; k < count; ++k) {
    const direction = (c, azimuth) => {
      const s = Math.sqrt(Math.max(0, 1 - c * c));
      return new THREE.Vector3(s * Math.cos(azimuth), s * Math.sin(azimuth), c);
    };
    const i = direction(2 * random() - 1, 2 * Math.PI * random());
    const j = direction(random(), 2 * Math.PI * random());
    const q = new THREE.Quaternion(random() - 0.5, random() - 0.5, random() - 0.5, random() - 0.5).normalize();
    out.push({i, j, world: {i: i.clone().applyQuaternion(q), j: j.clone().applyQuaternion(q),
                            n: new THREE.Vector3(0, 0, 1).applyQuaternion(q)}});
  }
  return out;
}

const kVertex = `void main() {  // one triangle covering the viewport
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}`;

async function main() {
  const count = Number(params.get('points') ?? 1024);
  const tables = await GanzfeldTables.fromManifest(params.get('tables'));
  const renderer = new THREE.WebGLRenderer({canvas: document.createElement('canvas')});
  const list = points(count, generator(Number(params.get('seed') ?? 1)));
  const directions = new Float32Array(4 * count * 3);
  list.forEach((p, k) => {
    [p.world.i, p.world.j, p.world.n].forEach((v, row) => directions.set([v.x, v.y, v.z, 0], 4 * (row * count + k)));
  });
  const pointTexture = new THREE.DataTexture(directions, count, 3, THREE.RGBAFormat, THREE.FloatType);
  pointTexture.needsUpdate = true;
  const target = new THREE.WebGLRenderTarget(count, 1, {type: THREE.FloatType, depthBuffer: false});
  const scene = new THREE.Scene(), camera = new THREE.Camera();
  const triangle = new THREE.Mesh(new THREE.BufferGeometry(), null);
  triangle.geometry.setDrawRange(0, 3);
  triangle.frustumCulled = false;
  scene.add(triangle);
  const sets = [];
  for (const roughness of tables.roughnessValues) {
    const set = tables.set(roughness);
    triangle.material = new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: kVertex,
      fragmentShader: `precision highp float;
uniform highp sampler2D points;
${ganzfeldParsChunk(set)}
out vec4 color;
void main() {
  int k = int(gl_FragCoord.x);
  vec3 i = texelFetch(points, ivec2(k, 0), 0).xyz, j = texelFetch(points, ivec2(k, 1), 0).xyz;
  vec3 n = texelFetch(points, ivec2(k, 2), 0).xyz;
  vec3 sky = gz_three_sky(i, j, n, vec3(0.0, 1.0, 0.0), 1.0);
  vec3 ganzfeld = gz_three_ganzfeld(j, n, vec3(0.0, 1.0, 0.0), 1.0);
  color = vec4(sky.x, sky.y, ganzfeld.x, ganzfeld.y);
}`,
      uniforms: {points: {value: pointTexture}, gzSkyF0: {value: tableTexture(set.g0)}, gzSkyF1: {value: tableTexture(set.g1)},
                 gzGanzfeldF0: {value: tableTexture(set.h0)}, gzGanzfeldF1: {value: tableTexture(set.h1)}},
    });
    renderer.setRenderTarget(target);
    renderer.render(scene, camera);
    const pixels = new Float32Array(4 * count);
    renderer.readRenderTargetPixels(target, 0, 0, count, 1, pixels);
    renderer.setRenderTarget(null);
    sets.push({roughness, models: {g0: set.g0.model, g1: set.g1.model, h0: set.h0.model, h1: set.h1.model},
               values: Array.from(pixels)});
  }
  report({webgl2: true, points: list.map((p) => [p.i.x, p.i.y, p.i.z, p.j.x, p.j.y, p.j.z]), sets});
}

main().catch((error) => report({error: error.message}));
