// The table reader, the table set and the material check without a browser (node --test; ctest
// threejs_unit). Tables are baked by the ganzfeld executable of $GANZFELD (default build/ganzfeld)
// and exported with export-glsl; the refusals are files ganzfeld wrote, or such files with one
// key/value changed (rewriteKtx2), served over HTTP by a server in this process, and a real
// `ganzfeld serve` for the service's own errors.
import {after, before, describe, test} from 'node:test';
import assert from 'node:assert/strict';
import {execFileSync, spawn} from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import {fileURLToPath} from 'node:url';
import * as THREE from 'three';
import {GanzfeldTables, glslIdentifier, makeTable, readKtx2, tableTexture, toGanzfeldScene} from '../src/index.js';

const here = path.dirname(fileURLToPath(import.meta.url));
const repository = path.resolve(here, '../../..');
const ganzfeld = process.env.GANZFELD ?? path.join(repository, 'build/ganzfeld');
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'ganzfeld-three-'));
let server, base, serve, serviceBase;

/// bake + export-glsl: dir/NAME.glsl and dir/NAME.ktx2.
function table(name, model, law, res, extra = []) {
  const exr = path.join(dir, `${name}.exr`);
  execFileSync(ganzfeld, ['bake', '--model', model, '--law', law, '--res', res, '--tol', '1e-4', ...extra, '-o', exr,
                          '--quiet']);
  execFileSync(ganzfeld, ['export-glsl', exr, '-o', path.join(dir, `${name}.glsl`), '--quiet']);
}

/// The KTX2 file `bytes` with key `key` set to `value` (export/texture_file.cpp's layout: header,
/// index, level index, data format descriptor, key/value data, level data).
function rewriteKtx2(bytes, key, value) {
  const texture = readKtx2(bytes, 'fixture');
  texture.keyValues[key] = value;
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const dfdAt = view.getUint32(48, true), dfdLength = view.getUint32(52, true);
  const levelAt = Number(view.getBigUint64(80, true)), levelLength = Number(view.getBigUint64(88, true));
  const encoder = new TextEncoder();
  const entries = [];
  for (const k of Object.keys(texture.keyValues).sort()) {
    const payload = new Uint8Array([...encoder.encode(k), 0, ...encoder.encode(texture.keyValues[k]), 0]);
    const entry = new Uint8Array(4 + ((payload.length + 3) & ~3));
    new DataView(entry.buffer).setUint32(0, payload.length, true);
    entry.set(payload, 4);
    entries.push(entry);
  }
  const kvd = Buffer.concat(entries);
  const kvdAt = dfdAt + dfdLength, newLevelAt = (kvdAt + kvd.length + 3) & ~3;
  const out = Buffer.alloc(newLevelAt + levelLength);
  Buffer.from(bytes.subarray(0, kvdAt)).copy(out);
  kvd.copy(out, kvdAt);
  Buffer.from(bytes.subarray(levelAt, levelAt + levelLength)).copy(out, newLevelAt);
  out.writeUInt32LE(kvdAt, 56);
  out.writeUInt32LE(kvd.length, 60);
  out.writeBigUInt64LE(BigInt(newLevelAt), 80);
  return out;
}

before(async () => {
  for (const f0 of [0, 1]) {
    table(`g${f0}`, `ggx:roughness=0.5,f0=${f0}`, 'g', '5x5x5');
    table(`h${f0}`, `ggx:roughness=0.5,f0=${f0}`, 'h', '9');
  }
  table('specular', 'specular:alpha=8', 'g', '5x5x5');
  // format version 6's one-fetch table: warped frame, its bound for the GPU's filter (docs/lut-format.md)
  table('warped', 'ggx:roughness=0.5,f0=1', 'g', '5x9x5', ['--frame', 'warped', '--filter', 'hardware']);
  table('separable', 'ggx:roughness=0.5,g2=separable', 'g', '5x5x5');
  table('albedo', 'ggx:roughness=0.5', 'a', '9');
  const g1 = fs.readFileSync(path.join(dir, 'g1.ktx2'));
  fs.writeFileSync(path.join(dir, 'version3.ktx2'), rewriteKtx2(g1, 'ganzfeld.format_version', '3'));
  fs.writeFileSync(path.join(dir, 'anisotropic.ktx2'),
                   rewriteKtx2(g1, 'ganzfeld.model', 'ggx:alpha_x=0.2,alpha_y=0.5,f0=1,g2=height-correlated'));
  server = http.createServer((request, response) => {
    const file = path.join(dir, decodeURIComponent(new URL(request.url, 'http://x').pathname));
    if (!fs.existsSync(file)) {
      response.writeHead(404).end('not found');
      return;
    }
    response.writeHead(200).end(fs.readFileSync(file));
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  base = `http://127.0.0.1:${server.address().port}`;
});

after(async () => {
  server?.close();
  if (serve) {
    serve.kill('SIGTERM');
    await new Promise((resolve) => serve.once('exit', resolve));
  }
  fs.rmSync(dir, {recursive: true, force: true});
});

const load = (name, glsl = name) => GanzfeldTables.fromFiles([{glsl: `${base}/${glsl}.glsl`, ktx2: `${base}/${name}.ktx2`}]);

describe('the reader', () => {
  test('reads what export-glsl wrote: values, metadata, the GLSL function', async () => {
    const tables = await GanzfeldTables.fromFiles(['g0', 'g1', 'h0', 'h1'].map((n) => ({glsl: `${base}/${n}.glsl`,
                                                                                      ktx2: `${base}/${n}.ktx2`})));
    const g1 = tables.find(0.5, 'g', 1);
    assert.equal(g1.model, 'ggx:alpha=0.25,f0=1,g2=height-correlated');
    assert.equal(g1.functionName, 'gz_ggx_alpha_0_25_f0_1_g2_height_correlated_g');
    assert.deepEqual([g1.width, g1.height, g1.depth], [5, 5, 5]);
    assert.ok(g1.lookupError > 0);
    // the values are those `ganzfeld info --json` reads from the EXR... compared through sample at
    // a node: (i.n, j.n, phi) = (1, 1, 0) is node (4, 4, 0), the last depth and height, first column
    const sampled = JSON.parse(execFileSync(ganzfeld, ['sample', path.join(dir, 'g1.exr'), '--i', '0,0,1', '--j', '0,0,1',
                                                       '--json']).toString()).value;
    assert.equal(g1.texels[(4 * 5 + 4) * 5 + 0], Math.fround(sampled));
    assert.deepEqual(tables.roughnessValues, [0.5]);
  });

  test('a one-fetch table is read with the GPU\'s linear filter, a texelFetch table with nearest', async () => {
    const [warped, g1] = await Promise.all([load('warped'), load('g1')]);
    const w = warped.find(0.5, 'g', 1), t = g1.find(0.5, 'g', 1);
    assert.equal(w.formatVersion, '6');
    assert.equal(w.filter, 'hardware');
    assert.equal(t.filter, 'texel-fetch');
    const wt = tableTexture(w), tt = tableTexture(t);
    assert.deepEqual([wt.minFilter, wt.magFilter], [THREE.LinearFilter, THREE.LinearFilter]);
    assert.deepEqual([tt.minFilter, tt.magFilter], [THREE.NearestFilter, THREE.NearestFilter]);
    assert.match(w.glsl, /gz_lookup3_filtered\(/);
  });

  test('glslIdentifier is export/glsl.h\'s', () => {
    assert.equal(glslIdentifier('specular:alpha=8_g'), 'gz_specular_alpha_8_g');
    assert.equal(glslIdentifier('a--b..'), 'gz_a_b');
  });

  const refusals = [
    ['version3', 'format version 3; allowed: 1, 2, 4, 5'],
    ['anisotropic', "the anisotropic model 'ggx:alpha_x=0.2"],
    ['specular', "model 'specular:alpha=8'; allowed: ggx:alpha=A,f0=0|1,g2=height-correlated"],
    ['separable', 'g2 = separable'],
    ['albedo', 'holds law a; allowed: g'],
  ];
  for (const [name, message] of refusals)
    test(`refuses ${name}, naming the table and what is allowed`, async () => {
      await assert.rejects(load(name, name === 'version3' || name === 'anisotropic' ? 'g1' : name), (error) => {
        assert.match(error.message, new RegExp(`'${base}/${name}.ktx2'`));
        assert.ok(error.message.includes(message), error.message);
        return true;
      });
    });

  test('refuses the GLSL of another table', async () => {
    await assert.rejects(load('g1', 'g0'), /the GLSL of table .*g1.ktx2' is for law g of ggx:alpha=0.25,f0=0/);
  });

  test('refuses a missing file with its URL and status', async () => {
    await assert.rejects(load('nosuchtable'), new RegExp(`'${base}/nosuchtable.(glsl|ktx2)': HTTP 404`));
    await assert.rejects(GanzfeldTables.fromManifest(`${base}/nosuch/manifest.json`), /manifest .*: HTTP 404/);
  });

  test('refuses bytes that are not KTX2', () => {
    assert.throws(() => makeTable(new Uint8Array(100), '', 'junk.ktx2'), /'junk.ktx2' is not a ganzfeld KTX2 table: no KTX 2.0/);
  });
});

describe('materials', () => {
  let tables;
  before(async () => {
    tables = await GanzfeldTables.fromFiles(['g0', 'g1', 'h0', 'h1'].map((n) => ({glsl: `${base}/${n}.glsl`,
                                                                                 ktx2: `${base}/${n}.ktx2`})));
  });

  test('apply states the lookup errors of the tables', () => {
    const material = new THREE.MeshStandardMaterial({roughness: 0.5});
    const state = tables.apply(material);
    assert.equal(state.lookupError.sky, Math.max(tables.find(0.5, 'g', 0).lookupError, tables.find(0.5, 'g', 1).lookupError));
    assert.equal(state.lookupError.ambient, Math.max(tables.find(0.5, 'h', 0).lookupError, tables.find(0.5, 'h', 1).lookupError));
    assert.equal(material.userData.ganzfeld, state);
    tables.remove(material);
    assert.equal(material.userData.ganzfeld, undefined);
    assert.equal(material.onBeforeCompile, THREE.Material.prototype.onBeforeCompile);
  });

  test('a roughness outside the tables throws and leaves the material as it was', () => {
    const material = new THREE.MeshStandardMaterial({roughness: 0.3});
    assert.throws(() => tables.apply(material), /roughness 0.3 is outside the tables of files .*; allowed: 0.5/);
    assert.equal(material.onBeforeCompile, THREE.Material.prototype.onBeforeCompile);
    assert.equal(material.userData.ganzfeld, undefined);
  });

  test('a roughness changed after apply throws at the next draw', () => {
    const material = new THREE.MeshStandardMaterial({roughness: 0.5});
    tables.apply(material);
    material.roughness = 0.6;
    assert.throws(() => material.onBeforeRender(), /has roughness 0.6 but shades with the tables of roughness 0.5/);
  });

  test('refuses what the tables do not describe', () => {
    const cases = [
      [new THREE.MeshLambertMaterial(), /is a MeshLambertMaterial; allowed: MeshStandardMaterial, MeshPhysicalMaterial/],
      [new THREE.MeshPhysicalMaterial({roughness: 0.5, clearcoat: 1}), /uses clearcoat = 1; allowed: anisotropy, clearcoat/],
      [Object.assign(new THREE.MeshStandardMaterial({roughness: 0.5}), {roughnessMap: new THREE.Texture()}), /roughnessMap/],
    ];
    for (const [material, message] of cases) {
      assert.throws(() => tables.apply(material), message);
      assert.equal(material.userData.ganzfeld, undefined);
    }
    assert.throws(() => tables.apply(new THREE.MeshStandardMaterial({roughness: 0.5}), {diffuse: 'x'}),
                  /diffuse 'x' is not a mode; allowed: three, lambert/);
  });

  test('the material\'s fragment shader gets the exported functions and the lights', () => {
    const material = new THREE.MeshStandardMaterial({roughness: 0.5});
    tables.apply(material, {diffuse: 'lambert'});
    const shader = {fragmentShader: THREE.ShaderLib.standard.fragmentShader, uniforms: {}};
    material.onBeforeCompile(shader);
    for (const law of ['g', 'h'])
      for (const f0 of [0, 1]) assert.ok(shader.fragmentShader.includes(`float ${tables.find(0.5, law, f0).functionName}(`));
    assert.ok(shader.fragmentShader.includes('vec3 irradiance = vec3( 0.0 );'));
    assert.ok(shader.uniforms.gzSkyF1.value.isData3DTexture);
  });
});

describe('the service', () => {
  before(async () => {
    serve = spawn(ganzfeld, ['serve', '--port', '0', '--cache', path.join(dir, 'cache')], {stdio: ['ignore', 'ignore', 'pipe']});
    serviceBase = await new Promise((resolve, reject) => {
      let text = '';
      serve.stderr.on('data', (chunk) => {
        text += chunk;
        const match = text.match(/listening on (http:\/\/127\.0\.0\.1:\d+)\//);
        if (match) resolve(match[1]);
      });
      serve.once('exit', () => reject(new Error(`serve exited: ${text}`)));
    });
  });

  // The tables are fetched concurrently: whichever request is refused first is the one reported.
  test('an HTTP error from the service is thrown with its message', async () => {
    await assert.rejects(GanzfeldTables.fromService(serviceBase, {roughness: [0.5], res: {g: '1x1x1', h: '9'}}),
                         /table .*'.*\/api\/(glsl|table)\?model=ggx%3Aroughness%3D0.5%2Cf0%3D[01]&law=g&res=1x1x1.*': HTTP 400: .*res/);
  });

  test('a roughness outside (0, 1] is refused before any request', async () => {
    await assert.rejects(GanzfeldTables.fromService(serviceBase, {roughness: [1.5]}), /roughness 1.5 is not allowed; allowed: \(0, 1\]/);
  });

  test('tables from the service load', async () => {
    const tables = await GanzfeldTables.fromService(serviceBase, {roughness: [0.5], res: {g: '5x5x5', h: '9'}});
    assert.deepEqual(tables.roughnessValues, [0.5]);
  });
});

describe('the scene file', () => {
  test('a three.js scene as ganzfeld sees it', () => {
    const scene = new THREE.Scene();
    const material = new THREE.MeshStandardMaterial({color: new THREE.Color(0.5, 0.25, 1), roughness: 0.5, metalness: 0.5});
    material.name = 'm';
    const sphere = new THREE.Mesh(new THREE.SphereGeometry(2, 8, 4), material);
    sphere.position.set(1, 2, 3);
    scene.add(sphere);
    const hemisphere = new THREE.HemisphereLight(new THREE.Color(1, 1, 1), new THREE.Color(0.5, 0.5, 0.5), Math.PI);
    hemisphere.position.set(0, 2, 0);
    scene.add(hemisphere, new THREE.AmbientLight(new THREE.Color(1, 1, 1), Math.PI));
    const camera = new THREE.PerspectiveCamera(40, 2, 0.1, 10);
    camera.position.set(0, 0, 5);
    const file = toGanzfeldScene(scene, camera, {width: 20, height: 10});
    assert.deepEqual(file.camera, {width: 20, height: 10, eye: [0, 0, 5], target: [0, 0, 4], up: [0, 1, 0], fov_deg: 40,
                                   background: [0, 0, 0]});
    assert.deepEqual(file.objects, [{shape: 'sphere', center: [1, 2, 3], radius: 2, material: 'm'}]);
    // f0 = mix(0.04, colour, 0.5), f90 = 1; diffuse = colour (1 - 0.5); three lobes, colours x 3
    const f0 = [0.27, 0.145, 0.52];
    assert.deepEqual(file.materials.m.lobes.map((l) => l.model), ['lambert', 'ggx:roughness=0.5,f0=0', 'ggx:roughness=0.5,f0=1']);
    file.materials.m.lobes[1].color.forEach((c, k) => assert.ok(Math.abs(c - 3 * (1 - f0[k])) < 1e-12, `${c}`));
    file.materials.m.lobes[2].color.forEach((c, k) => assert.ok(Math.abs(c - 3 * f0[k]) < 1e-12, `${c}`));
    assert.deepEqual(file.lights, [{type: 'hemispherical', pole: [0, 1, 0], radiance: [1, 1, 1]},
                                   {type: 'hemispherical', pole: [0, -1, 0], radiance: [0.5, 0.5, 0.5]},
                                   {type: 'ganzfeld', radiance: [1, 1, 1]}]);
  });

  test('the committed example scene file is what examples/three/scene.js makes', () => {
    const committed = fs.readFileSync(path.join(repository, 'examples/three/scene.json'), 'utf8');
    const made = execFileSync(process.execPath, [path.join(here, '../bin/scene-file.js'),
                                                 path.join(repository, 'examples/three/scene.js'), '960x540', 'extended']);
    assert.equal(made.toString(), committed, 'regenerate it: docs/three.md, "The example"');
  });
});
