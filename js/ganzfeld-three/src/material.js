// MeshStandardMaterial / MeshPhysicalMaterial under a HemisphereLight and an AmbientLight, shaded
// by ganzfeld's laws (Koenderink & Pont, "Material Properties and Extended Sources for Surface
// Rendering": a uniform sky with pole i gives radiance N g(i, j), a Ganzfeld N h(j)).
//
// three.js (0.187, src/renderers/shaders/ShaderChunk/lights_fragment_begin.glsl.js) turns both
// lights into an irradiance E that only its diffuse lobe sees: E = mix(ground, sky, (1 + n.d)/2)
// for a hemisphere of direction d, E = colour for an ambient light. As radiance that is a sky of
// N = sky / pi on the side of d, a ground of N = ground / pi on the other (a sky with pole -d), and
// a Ganzfeld of N = colour / pi. This module adds what three.js leaves out, the GGX lobe's
// response to them, from ganzfeld's tables of g and h of ggx:alpha=R^2:
//   specular = sum over hemisphere lights of (sky G(d) + ground G(-d)) / pi + ambient H / pi,
//   G = f0 (g1 - g0) + f90 g0,  H = f0 (h1 - h0) + f90 h0,
// where g0, h0 are the laws of ggx:f0=0 (F = x^5) and g1, h1 of ggx:f0=1 (F = 1): Schlick's
// F = f0 (1 - x^5) + f90 x^5 (x = 1 - v.h) is linear in (f0, f90), so is f, so are g and h. f0 and
// f90 are three.js's own (material.specularColorBlended, material.specularF90: metalness, ior and
// specular maps included), per pixel. Lookups run in view space (only i.n, j.n and the angle
// between their tangential parts enter; docs/shaders.md).
//
// The diffuse lobe: `diffuse: 'three'` (default) keeps three.js's own diffuse response to these
// lights (Lambert, scaled by 1 - its DFG estimate of the specular albedo at n.v); `'lambert'`
// replaces it by the plain Lambert lobe, g = (1 + i.n)/2, h = 1: the material is then exactly the
// mixture Lambert (colour = diffuse contribution) + ggx:f0=0 (1 - f0) + ggx:f0=1 (f0) that
// `ganzfeld render` shades (the pixel test, tests/threejs_test.sh).
import * as THREE from 'three';
import {kRoughnessTolerance} from './table.js';

export const kDiffuseModes = ['three', 'lambert'];
/// MeshPhysicalMaterial layers the tables do not describe: shading them under these lights would
/// be three.js's or nothing, so a material using one is refused.
export const kUnsupportedLayers = ['anisotropy', 'clearcoat', 'dispersion', 'diffuseRoughness', 'iridescence',
                                   'retroreflectivity', 'sheen', 'transmission'];

/// A three.js texture of a table (./table.js), one float channel: nearest filtering for tables read
/// with texelFetch, linear for those whose exported lookup is one hardware-filtered texture()
/// (filter 'hardware', docs/lut-format.md); no mipmaps (export/glsl.h: the texture must be
/// complete without them).
export function tableTexture(table) {
  if (table.texture) return table.texture;
  const texture = table.law === 'g'
    ? new THREE.Data3DTexture(table.texels, table.width, table.height, table.depth)
    : new THREE.DataTexture(table.texels, table.width, 1);
  texture.format = THREE.RedFormat;
  texture.type = THREE.FloatType;
  texture.minFilter = texture.magFilter = table.filter === 'hardware' ? THREE.LinearFilter : THREE.NearestFilter;
  texture.wrapS = texture.wrapT = texture.wrapR = THREE.ClampToEdgeWrapping;
  texture.generateMipmaps = false;
  texture.unpackAlignment = 1;
  texture.needsUpdate = true;
  table.texture = texture;
  return texture;
}

/// The GLSL declarations of a set {g0, g1, h0, h1}: the samplers, the four exported functions
/// (their shared helpers once: export/glsl.h guards them) and the two Schlick combinations.
export function ganzfeldParsChunk(set) {
  const snippets = [set.g0, set.g1, set.h0, set.h1].map((t) => t.glsl).join('\n');
  return `
// ganzfeld-three (js/ganzfeld-three/src/material.js): g and h of ggx:alpha=${set.alpha}
uniform highp sampler3D gzSkyF0;
uniform highp sampler3D gzSkyF1;
uniform highp sampler2D gzGanzfeldF0;
uniform highp sampler2D gzGanzfeldF1;
${snippets}
// Schlick's F is linear in (f0, f90): law = f0 (law of f0 = 1 - law of f0 = 0) + f90 (law of f0 = 0).
vec3 gz_three_sky(vec3 pole, vec3 j, vec3 n, vec3 f0, float f90) {
  float law0 = ${set.g0.functionName}(gzSkyF0, pole, j, n);
  float law1 = ${set.g1.functionName}(gzSkyF1, pole, j, n);
  return f0 * (law1 - law0) + f90 * law0;
}
vec3 gz_three_ganzfeld(vec3 j, vec3 n, vec3 f0, float f90) {
  float law0 = ${set.h0.functionName}(gzGanzfeldF0, j, n);
  float law1 = ${set.h1.functionName}(gzGanzfeldF1, j, n);
  return f0 * (law1 - law0) + f90 * law0;
}
`;
}

/// The shading, after three.js's own lights (lights_fragment_end): radiance = colour / pi, in view
/// space, j moved onto the horizon where interpolated normals put it below (as `render` does).
export function ganzfeldLightsChunk(diffuse) {
  return `
#if defined( RE_IndirectSpecular )
	{
		vec3 gzNormal = geometryNormal;
		vec3 gzView = gz_clamp_to_horizon( geometryViewDir, gzNormal );
		vec3 gzF0 = material.specularColorBlended;
		float gzF90 = material.specularF90;
		vec3 gzSpecular = ambientLightColor * gz_three_ganzfeld( gzView, gzNormal, gzF0, gzF90 );
		#if ( NUM_HEMI_LIGHTS > 0 )
		#pragma unroll_loop_start
		for ( int i = 0; i < NUM_HEMI_LIGHTS; i ++ ) {
			gzSpecular += hemisphereLights[ i ].skyColor * gz_three_sky( hemisphereLights[ i ].direction, gzView, gzNormal, gzF0, gzF90 )
				+ hemisphereLights[ i ].groundColor * gz_three_sky( - hemisphereLights[ i ].direction, gzView, gzNormal, gzF0, gzF90 );
		}
		#pragma unroll_loop_end
		#endif
		reflectedLight.indirectSpecular += gzSpecular * RECIPROCAL_PI;
${diffuse === 'lambert' ? `
		vec3 gzIrradiance = getAmbientLightIrradiance( ambientLightColor );
		#if ( NUM_HEMI_LIGHTS > 0 )
		#pragma unroll_loop_start
		for ( int i = 0; i < NUM_HEMI_LIGHTS; i ++ ) {
			gzIrradiance += getHemisphereLightIrradiance( hemisphereLights[ i ], geometryNormal );
		}
		#pragma unroll_loop_end
		#endif
		reflectedLight.indirectDiffuse += gzIrradiance * BRDF_Lambert( material.diffuseContribution );` : ''}
	}
#endif
`;
}

/// three.js's lights_fragment_begin without the ambient and hemisphere irradiance (for
/// diffuse: 'lambert', where the module shades them); throws if three.js's text is not the one
/// this module was written against.
function lightsBeginWithoutExtendedSources() {
  const replacements = [
    ['vec3 irradiance = getAmbientLightIrradiance( ambientLightColor );', 'vec3 irradiance = vec3( 0.0 );'],
    ['irradiance += getHemisphereLightIrradiance( hemisphereLights[ i ], geometryNormal );', ''],
  ];
  let chunk = THREE.ShaderChunk.lights_fragment_begin;
  for (const [from, to] of replacements) {
    if (chunk.split(from).length !== 2)
      throw new Error(`ganzfeld-three: three.js ${THREE.REVISION}'s lights_fragment_begin lacks '${from}'; ` +
                      'allowed: three.js 0.187 (the peer dependency)');
    chunk = chunk.replace(from, to);
  }
  return chunk;
}

/// Replaces `include` in `source` by `text` (which may contain it); throws if it is not there once.
function inject(source, include, text, material) {
  if (source.split(include).length !== 2)
    throw new Error(`ganzfeld-three: the shader of material '${material.name || material.uuid}' has no single ` +
                    `'${include}'; allowed: MeshStandardMaterial and MeshPhysicalMaterial of three.js 0.187`);
  return source.replace(include, text);
}

/// Materials the module shades, each with the onBeforeCompile and onBeforeRender it had before
/// (restored by removeGanzfeld).
const installed = new WeakMap();

/// Throws unless `material` is one this module shades: a MeshStandardMaterial or
/// MeshPhysicalMaterial without a roughness map or the layers of kUnsupportedLayers.
export function checkMaterial(material) {
  const name = material?.name || material?.uuid || String(material);
  if (!material?.isMeshStandardMaterial)
    throw new Error(`ganzfeld-three: material '${name}' is a ${material?.type ?? typeof material}; allowed: ` +
                    'MeshStandardMaterial, MeshPhysicalMaterial');
  if (material.roughnessMap)
    throw new Error(`ganzfeld-three: material '${name}' has a roughnessMap; allowed: one roughness per material ` +
                    '(the tables are per roughness)');
  for (const layer of kUnsupportedLayers)
    if (material[layer] > 0)
      throw new Error(`ganzfeld-three: material '${name}' uses ${layer} = ${material[layer]}; allowed: ` +
                      `${kUnsupportedLayers.join(', ')} = 0 (the tables describe the base GGX layer only)`);
}

/// Makes `material` shade with the table set `set` ({alpha, roughness, g0, g1, h0, h1}, checked by
/// the caller to match material.roughness). Returns what material.userData.ganzfeld holds.
export function installGanzfeld(material, set, diffuse) {
  if (!kDiffuseModes.includes(diffuse))
    throw new Error(`ganzfeld-three: diffuse '${diffuse}' is not a mode; allowed: ${kDiffuseModes.join(', ')}`);
  checkMaterial(material);
  const previous = installed.has(material) ? installed.get(material).onBeforeCompile : material.onBeforeCompile;
  const textures = {gzSkyF0: set.g0, gzSkyF1: set.g1, gzGanzfeldF0: set.h0, gzGanzfeldF1: set.h1};
  const pars = ganzfeldParsChunk(set), lights = ganzfeldLightsChunk(diffuse);
  const begin = diffuse === 'lambert' ? lightsBeginWithoutExtendedSources() : null;
  const key = `ganzfeld-three:${diffuse}:${Object.values(textures).map((t) => t.functionName).join(',')}`;
  material.onBeforeCompile = function (shader, renderer) {
    previous.call(this, shader, renderer);
    checkMaterial(this);
    for (const [uniform, table] of Object.entries(textures)) shader.uniforms[uniform] = {value: tableTexture(table)};
    let source = inject(shader.fragmentShader, '#include <lights_physical_pars_fragment>',
                        `#include <lights_physical_pars_fragment>\n${pars}`, this);
    if (begin) source = inject(source, '#include <lights_fragment_begin>', begin, this);
    shader.fragmentShader = inject(source, '#include <lights_fragment_end>', `#include <lights_fragment_end>\n${lights}`, this);
  };
  material.customProgramCacheKey = () => key;
  // three.js does not recompile when the roughness changes, so the check is made per draw: a
  // roughness the tables do not describe throws instead of shading with the wrong tables.
  const previousRender = installed.has(material) ? installed.get(material).onBeforeRender : material.onBeforeRender;
  material.onBeforeRender = function (...args) {
    if (Math.abs(this.roughness - set.roughness) > kRoughnessTolerance)
      throw new Error(`ganzfeld-three: material '${this.name || this.uuid}' has roughness ${this.roughness} but shades ` +
                      `with the tables of roughness ${set.roughness}; apply the tables again for the new roughness`);
    previousRender.apply(this, args);
  };
  const tables = Object.values(textures);
  const state = {
    roughness: set.roughness,
    diffuse,
    tables: tables.map((t) => ({name: t.name, model: t.model, law: t.law, lookupError: t.lookupError})),
    // G and H are convex combinations of the f0 = 0 and f0 = 1 lookups when f90 = 1 (three.js's
    // MeshStandardMaterial), so their error is at most the larger of the two tables' bounds.
    lookupError: {sky: Math.max(set.g0.lookupError, set.g1.lookupError),
                  ambient: Math.max(set.h0.lookupError, set.h1.lookupError)},
  };
  installed.set(material, {onBeforeCompile: previous, onBeforeRender: previousRender});
  material.userData.ganzfeld = state;
  material.needsUpdate = true;
  return state;
}

/// Restores three.js's own shading of `material` (the module's toggle).
export function removeGanzfeld(material) {
  if (!installed.has(material)) return;
  material.onBeforeCompile = installed.get(material).onBeforeCompile;
  material.onBeforeRender = installed.get(material).onBeforeRender;
  installed.delete(material);
  delete material.customProgramCacheKey;  // the prototype's
  delete material.userData.ganzfeld;
  material.needsUpdate = true;
}
