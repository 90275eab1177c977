// The example page (docs/three.md): examples/three/scene.js rendered by three.js, its
// HemisphereLight and AmbientLight shaded by ganzfeld-three or by three.js alone (the checkbox).
//
// URL parameters:
//   tables=URL      the manifest export-glsl --scene wrote (default tables/manifest.json), or
//   service=URL     `ganzfeld serve` at URL (same origin): the tables of every roughness, baked there,
//                   with max_error=E (default 2e-2, what the manifest's tables are baked to)
//   size=WxH        the canvas in pixels (default 960x540)
//   diffuse=three|lambert   the module's diffuse mode (js/ganzfeld-three/src/material.js)
//   mode=ganzfeld|stock     the first state of the checkbox;  lights=all|extended (extended: no sun)
//   test=1          render once without antialiasing and write the pixels (RGBA, rows top first,
//                   base64) as JSON into <pre id="result">, for tests/threejs_test.sh
//   bench=R&frames=F  R rounds of F frames per mode, alternating, each frame synchronized with
//                   readPixels; the milliseconds per frame as JSON (scripts/gen-three-docs)
import * as THREE from 'three';
import {GanzfeldTables} from 'ganzfeld-three';
import {buildExampleScene, kRoughness} from './scene.js';

const params = new URLSearchParams(location.search);
const result = document.getElementById('result');
const report = (object) => { result.textContent = JSON.stringify(object); };

function base64(bytes) {
  let text = '';
  for (let k = 0; k < bytes.length; k += 0x8000) text += String.fromCharCode(...bytes.subarray(k, k + 0x8000));
  return btoa(text);
}

/// The canvas's pixels as RGBA bytes, rows top first.
function readCanvas(gl, width, height) {
  const pixels = new Uint8Array(4 * width * height), rows = new Uint8Array(4 * width * height);
  gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
  for (let y = 0; y < height; ++y) rows.set(pixels.subarray(4 * (height - 1 - y) * width, 4 * (height - y) * width), 4 * y * width);
  return rows;
}

async function main() {
  const [width, height] = (params.get('size') ?? '960x540').split('x').map(Number);
  const measuring = params.has('test') || params.has('bench');
  const canvas = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({canvas, antialias: !measuring, alpha: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.setClearColor(0x000000, 0);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = THREE.NoToneMapping;
  const gl = renderer.getContext();

  const {scene, camera, materials} = buildExampleScene(THREE, width / height);
  const sun = scene.getObjectByName('sun');
  sun.visible = params.get('lights') !== 'extended';
  const service = params.get('service');
  const tables = service
    ? await GanzfeldTables.fromService(service, {roughness: kRoughness, maxError: Number(params.get('max_error') ?? 2e-2)})
    : await GanzfeldTables.fromManifest(params.get('tables') ?? 'tables/manifest.json');
  const diffuse = params.get('diffuse') ?? 'three';
  const setMode = (ganzfeld) => {
    for (const material of materials) {
      if (ganzfeld) tables.apply(material, {diffuse});
      else tables.remove(material);
    }
  };
  const ganzfeldBox = document.getElementById('ganzfeld'), sunBox = document.getElementById('sun');
  ganzfeldBox.checked = params.get('mode') !== 'stock';
  sunBox.checked = sun.visible;
  setMode(ganzfeldBox.checked);

  // The honest headline, per material: the lookup error of the tables it shades with.
  const rows = [['material', 'roughness', 'metalness', 'sky (g) lookup error', 'ambient (h) lookup error']];
  for (const material of materials) {
    const state = tables.apply(material, {diffuse});
    rows.push([material.name, material.roughness, material.metalness, state.lookupError.sky.toExponential(2),
               state.lookupError.ambient.toExponential(2)]);
  }
  setMode(ganzfeldBox.checked);
  document.getElementById('errors').innerHTML =
    rows.map((r, k) => `<tr>${r.map((c) => (k ? `<td>${c}</td>` : `<th>${c}</th>`)).join('')}</tr>`).join('');

  if (params.has('test')) {
    renderer.render(scene, camera);
    report({webgl2: true, width, height, mode: ganzfeldBox.checked ? 'ganzfeld' : 'stock', diffuse,
            rgba: base64(readCanvas(gl, width, height)), lookupErrors: rows.slice(1)});
    return;
  }
  if (params.has('bench')) {
    const rounds = Number(params.get('bench')), frames = Number(params.get('frames') ?? 10);
    const pixel = new Uint8Array(4);
    const frame = () => {
      renderer.render(scene, camera);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);  // waits for the frame
    };
    const times = {stock: [], ganzfeld: []};
    for (let round = 0; round < rounds; ++round)
      for (const mode of round % 2 ? ['ganzfeld', 'stock'] : ['stock', 'ganzfeld']) {
        setMode(mode === 'ganzfeld');
        frame();  // compiles (once) and warms up
        frame();
        const start = performance.now();
        for (let k = 0; k < frames; ++k) frame();
        times[mode].push((performance.now() - start) / frames);
      }
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    report({bench: times, width, height, frames, renderer: info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : '?',
            three: THREE.REVISION});
    return;
  }
  const draw = () => renderer.render(scene, camera);
  ganzfeldBox.addEventListener('change', () => { setMode(ganzfeldBox.checked); draw(); });
  sunBox.addEventListener('change', () => { sun.visible = sunBox.checked; draw(); });
  draw();
  document.getElementById('status').textContent = `tables: ${tables.source}`;
  report({ready: true});
}

main().catch((error) => {
  const status = document.getElementById('status');
  status.className = 'error';
  status.textContent = error.message;
  report({error: error.message});
});
