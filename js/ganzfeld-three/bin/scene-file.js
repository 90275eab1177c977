#!/usr/bin/env node
// The ganzfeld scene file of a three.js scene module (src/scene.js: toGanzfeldScene):
//   node bin/scene-file.js MODULE.js WIDTHxHEIGHT [all|extended] > SCENE.json
// MODULE.js exports buildExampleScene(THREE, aspect) -> {scene, camera} (examples/three/scene.js).
import * as THREE from 'three';
import path from 'node:path';
import {pathToFileURL} from 'node:url';
import {toGanzfeldScene} from '../src/scene.js';

const [module, size, lights = 'all'] = process.argv.slice(2);
const match = /^(\d+)x(\d+)$/.exec(size ?? '');
if (!module || !match) {
  console.error('usage: scene-file.js MODULE.js WIDTHxHEIGHT [all|extended]');
  process.exit(2);
}
try {
  const width = Number(match[1]), height = Number(match[2]);
  const {buildExampleScene} = await import(pathToFileURL(path.resolve(module)).href);
  const {scene, camera} = buildExampleScene(THREE, width / height);
  process.stdout.write(JSON.stringify(toGanzfeldScene(scene, camera, {width, height, lights}), null, 1) + '\n');
} catch (error) {
  console.error(`scene-file.js: ${error.message}`);
  process.exit(2);
}
