// A three.js scene as a ganzfeld scene file (as examples/default.json): what
// `ganzfeld bake scene`, `export-glsl --scene` and `render --scene` read, so that ganzfeld bakes
// exactly the tables the scene's materials need and renders the picture three.js should show.
//
//   camera            PerspectiveCamera: eye, target (eye + its direction), up, vertical fov
//   sphere meshes     {"shape": "sphere", center, radius} (SphereGeometry's radius x the uniform scale)
//   DirectionalLight  collimated, irradiance = colour x intensity, towards position - target
//   HemisphereLight   two skies (./material.js): radiance sky/pi about its direction d, ground/pi about -d
//   AmbientLight      a Ganzfeld of radiance colour/pi
//   MeshStandardMaterial / MeshPhysicalMaterial (roughness R, colour c, metalness m; f0, f90 as
//                     three.js's lights_physical_fragment computes them)
//                     lambert (colour c (1 - m)) + ggx:roughness=R,f0=0 (colour f90 - f0)
//                     + ggx:roughness=R,f0=1 (colour f0): ganzfeld's materials are partitive
//                     mixtures (the weights are normalized), so each of the k lobes gets weight 1/k
//                     and colour k x its share.
// Colours are three.js's working space (linear sRGB), as ganzfeld's are.
import * as THREE from 'three';
import {checkMaterial} from './material.js';

const round = (x) => Number(x.toPrecision(15)) + 0;  // + 0: no -0 in the file
const vec = (v) => [round(v.x), round(v.y), round(v.z)];
const rgb = (c, scale = 1) => [round(c.r * scale), round(c.g * scale), round(c.b * scale)];

/// f0 and f90 of a material as three.js 0.187 computes them (lights_physical_fragment.glsl.js):
/// MeshStandardMaterial f0 = mix(0.04, colour, metalness), f90 = 1; MeshPhysicalMaterial
/// f0 = mix(min(((ior - 1)/(ior + 1))^2 specularColor, 1) specularIntensity, colour, metalness),
/// f90 = mix(specularIntensity, 1, metalness).
export function schlickParameters(material) {
  const m = material.metalness;
  let dielectric = new THREE.Color(0.04, 0.04, 0.04), f90 = 1;
  if (material.isMeshPhysicalMaterial) {
    const r = ((material.ior - 1) / (material.ior + 1)) ** 2;
    const s = material.specularIntensity;
    dielectric = new THREE.Color(Math.min(r * material.specularColor.r, 1) * s, Math.min(r * material.specularColor.g, 1) * s,
                                 Math.min(r * material.specularColor.b, 1) * s);
    f90 = s + (1 - s) * m;
  }
  return {f0: dielectric.clone().lerp(material.color, m), f90};
}

/// The lobes of a material, as in the file header above.
function materialLobes(material) {
  checkMaterial(material);
  const {f0, f90} = schlickParameters(material);
  const R = material.roughness;
  const diffuse = material.color.clone().multiplyScalar(1 - material.metalness);
  const lobes = [];
  if (diffuse.r > 0 || diffuse.g > 0 || diffuse.b > 0) lobes.push({model: 'lambert', color: diffuse});
  const bias = new THREE.Color(f90 - f0.r, f90 - f0.g, f90 - f0.b);
  if (bias.r < 0 || bias.g < 0 || bias.b < 0)
    throw new Error(`ganzfeld-three: material '${material.name}' has f0 (${rgb(f0)}) above f90 (${f90}); allowed: f0 <= f90`);
  lobes.push({model: `ggx:roughness=${R},f0=0`, color: bias});
  lobes.push({model: `ggx:roughness=${R},f0=1`, color: f0});
  return {lobes: lobes.map((l) => ({weight: 1, model: l.model, color: rgb(l.color, lobes.length)}))};
}

/// The ganzfeld scene of `scene` seen by `camera` at width x height pixels. lights: 'all', or
/// 'extended' for the hemisphere and ambient lights alone (no collimated light: what the module
/// shades, and what `export-glsl --scene` accepts for models without a GLSL f).
export function toGanzfeldScene(scene, camera, {width, height, lights = 'all'} = {}) {
  if (!camera?.isPerspectiveCamera) throw new Error('ganzfeld-three: toGanzfeldScene needs a PerspectiveCamera');
  if (!(Number.isInteger(width) && Number.isInteger(height) && width > 0 && height > 0))
    throw new Error(`ganzfeld-three: image size ${width}x${height}; allowed: positive integers`);
  if (!['all', 'extended'].includes(lights)) throw new Error(`ganzfeld-three: lights '${lights}'; allowed: all, extended`);
  scene.updateMatrixWorld(true);
  camera.updateMatrixWorld(true);
  const eye = new THREE.Vector3().setFromMatrixPosition(camera.matrixWorld);
  const forward = camera.getWorldDirection(new THREE.Vector3());
  const up = new THREE.Vector3(0, 1, 0).transformDirection(camera.matrixWorld);
  const background = scene.background?.isColor ? rgb(scene.background) : [0, 0, 0];
  const out = {
    camera: {width, height, eye: vec(eye), target: vec(eye.clone().add(forward)), up: vec(up), fov_deg: round(camera.fov),
             background},
    materials: {},
    objects: [],
    lights: [],
  };
  const names = new Map();  // material -> its key in out.materials
  scene.traverseVisible((object) => {
    if (object.isMesh) {
      const geometry = object.geometry;
      if (geometry.type !== 'SphereGeometry')
        throw new Error(`ganzfeld-three: mesh '${object.name}' is a ${geometry.type}; allowed: SphereGeometry`);
      const scale = new THREE.Vector3().setFromMatrixScale(object.matrixWorld);
      if (Math.abs(scale.x - scale.y) > 1e-12 * scale.x || Math.abs(scale.x - scale.z) > 1e-12 * scale.x)
        throw new Error(`ganzfeld-three: mesh '${object.name}' is scaled unevenly (${vec(scale)}); allowed: a uniform scale`);
      if (!names.has(object.material)) {
        const key = object.material.name || `material_${names.size}`;
        names.set(object.material, key);
        out.materials[key] = materialLobes(object.material);
      }
      out.objects.push({shape: 'sphere', center: vec(new THREE.Vector3().setFromMatrixPosition(object.matrixWorld)),
                        radius: round(geometry.parameters.radius * scale.x), material: names.get(object.material)});
    } else if (object.isDirectionalLight) {
      if (lights === 'all') {
        const direction = new THREE.Vector3().setFromMatrixPosition(object.matrixWorld)
          .sub(new THREE.Vector3().setFromMatrixPosition(object.target.matrixWorld)).normalize();
        out.lights.push({type: 'collimated', direction: vec(direction), irradiance: rgb(object.color, object.intensity)});
      }
    } else if (object.isHemisphereLight) {
      const pole = new THREE.Vector3().setFromMatrixPosition(object.matrixWorld).normalize();
      out.lights.push({type: 'hemispherical', pole: vec(pole), radiance: rgb(object.color, object.intensity / Math.PI)});
      out.lights.push({type: 'hemispherical', pole: vec(pole.clone().negate()),
                       radiance: rgb(object.groundColor, object.intensity / Math.PI)});
    } else if (object.isAmbientLight) {
      out.lights.push({type: 'ganzfeld', radiance: rgb(object.color, object.intensity / Math.PI)});
    } else if (object.isLight) {
      throw new Error(`ganzfeld-three: light '${object.name}' is a ${object.type}; allowed: DirectionalLight, ` +
                      'HemisphereLight, AmbientLight');
    }
  });
  return out;
}
