// One ganzfeld table as three.js needs it: the values (a KTX2 file, ./ktx2.js), the GLSL function
// `ganzfeld export-glsl` (or /api/glsl) wrote for exactly that table, and the metadata that says
// what it holds and how good a lookup is. The lookup itself is the exported GLSL, unchanged
// (export/glsl.h: the GPU reproduces `ganzfeld sample` up to float arithmetic), so a new table
// scheme reaches three.js with the GLSL that comes with its tables.
//
// What this module accepts (anything else throws an Error naming the table and what is allowed):
//   format version  1 or 2 (docs/lut-format.md)
//   law             g (vignetting: the sky, 3-D) or h (darkening: the Ganzfeld, 1-D)
//   model           ggx, isotropic (alpha, not alpha_x/alpha_y), g2 = height-correlated (three.js's
//                   V_GGX_SmithCorrelated), f0 = 0 or 1: the pair that gives every f0 and f90
//                   (Schlick's F is linear in them; ./material.js)
import {readKtx2} from './ktx2.js';

export const kFormatVersions = ['1', '2', '4', '5', '6'];
export const kLaws = ['g', 'h'];
/// A material's roughness R matches a table of alpha when |sqrt(alpha) - R| is below this: the
/// canonical spec stores alpha = R^2 to double precision (ggx:roughness=0.7 is alpha=0.48999999999999994).
export const kRoughnessTolerance = 1e-6;

/// "gz_" + text with every run of characters outside [A-Za-z0-9] replaced by one '_', without a
/// trailing '_': export/glsl.h's glsl_identifier, hence the name of a table's function.
export function glslIdentifier(text) {
  let out = 'gz_';
  let pending = false;
  for (const c of text) {
    if (/[A-Za-z0-9]/.test(c)) {
      if (pending && !out.endsWith('_')) out += '_';
      pending = false;
      out += c;
    } else {
      pending = true;
    }
  }
  if (pending && !out.endsWith('_')) out += '_';
  if (out.endsWith('_') && out.length > 3) out = out.slice(0, -1);
  return out;
}

/// The parameters of a canonical ggx spec ("ggx:alpha=0.25,f0=1,g2=height-correlated"), or an
/// Error naming the table and what is allowed.
export function parseGgxSpec(spec, name) {
  const bad = (why) => new Error(`ganzfeld-three: table '${name}' holds ${why}; allowed: ` +
                                 'ggx:alpha=A,f0=0|1,g2=height-correlated (isotropic GGX, three.js\'s visibility)');
  const colon = spec.indexOf(':');
  const family = colon < 0 ? spec : spec.slice(0, colon);
  if (family !== 'ggx') throw bad(`model '${spec}'`);
  const parameters = {};
  for (const item of colon < 0 ? [] : spec.slice(colon + 1).split(',')) {
    const [key, value] = item.split('=');
    parameters[key] = value;
  }
  if ('alpha_x' in parameters || 'alpha_y' in parameters) throw bad(`the anisotropic model '${spec}'`);
  const alpha = Number(parameters.alpha ?? '0.5');
  if (!(alpha > 0 && alpha <= 1)) throw bad(`model '${spec}' with alpha ${parameters.alpha}`);
  const f0 = Number(parameters.f0 ?? '1');
  if (f0 !== 0 && f0 !== 1) throw bad(`model '${spec}' with f0 = ${parameters.f0}`);
  const g2 = parameters.g2 ?? 'height-correlated';
  if (g2 !== 'height-correlated') throw bad(`model '${spec}' with g2 = ${g2}`);
  return {alpha, roughness: Math.sqrt(alpha), f0};
}

/// The texture dimensions a table's GLSL declares ("// texture: sampler3D, ... width W (...),
/// height H (...), depth D (...)" or "width W, height 1") and the model and law of its header
/// ("// ganzfeld table: law L of MODEL"): export/glsl.cpp's table_comment.
function glslHeader(glsl, name) {
  const table = glsl.match(/^\/\/ ganzfeld table: law (\w+) of (.*)$/m);
  const texture = glsl.match(/^\/\/ texture: (sampler[23]D), .*?width (\d+)(?: \([^)]*\))?, height (\d+)(?: \([^)]*\))?(?:, depth (\d+))?/m);
  if (!table || !texture)
    throw new Error(`ganzfeld-three: the GLSL of table '${name}' is not what ganzfeld export-glsl writes ` +
                    '(no "// ganzfeld table:" or "// texture:" line)');
  return {law: table[1], model: table[2], sampler: texture[1],
          size: [Number(texture[2]), Number(texture[3]), Number(texture[4] ?? 1)]};
}

/// A table checked and ready to bind: {name, model, law, formatVersion, roughness, alpha, f0,
/// lookupError, nodeError, command, width, height, depth, texels (Float32Array, x fastest),
/// glsl (the exported snippet), functionName, sampler ('sampler3D' | 'sampler2D'), filter
/// ('texel-fetch' | 'hardware': format version 4's ganzfeld.filter, the lookup the bound covers)}.
/// `name` is where the table came from (a file or URL), used in every error.
export function makeTable(ktx2Bytes, glsl, name) {
  const texture = readKtx2(ktx2Bytes, name);
  const kv = texture.keyValues;
  const get = (key) => {
    if (!(key in kv)) throw new Error(`ganzfeld-three: table '${name}' lacks the key '${key}' (not written by ganzfeld)`);
    return kv[key];
  };
  const formatVersion = get('ganzfeld.format_version');
  if (!kFormatVersions.includes(formatVersion))
    throw new Error(`ganzfeld-three: table '${name}' has format version ${formatVersion}; allowed: ` +
                    `${kFormatVersions.join(', ')} (docs/lut-format.md)`);
  const law = get('ganzfeld.law');
  if (!kLaws.includes(law))
    throw new Error(`ganzfeld-three: table '${name}' holds law ${law}; allowed: g (a HemisphereLight's sky and ground), ` +
                    'h (an AmbientLight)');
  const model = get('ganzfeld.model');
  const ggx = parseGgxSpec(model, name);
  const lookupError = Number(get('ganzfeld.lookup_error'));
  if (!(lookupError >= 0 && Number.isFinite(lookupError)))
    throw new Error(`ganzfeld-three: table '${name}' states the lookup error '${kv['ganzfeld.lookup_error']}'; ` +
                    'allowed: a finite number >= 0');
  const is3d = law === 'g';
  if ((texture.depth > 1) !== is3d || (!is3d && texture.height !== 1))
    throw new Error(`ganzfeld-three: table '${name}' of law ${law} is a ${texture.width}x${texture.height}x${texture.depth} ` +
                    `texture; allowed: ${is3d ? 'a 3-D texture (g)' : 'a count x 1 texture (h)'}`);
  for (const value of texture.texels)
    if (!Number.isFinite(value)) throw new Error(`ganzfeld-three: table '${name}' holds a non-finite value; allowed: finite values`);

  if (typeof glsl !== 'string') throw new Error(`ganzfeld-three: table '${name}' comes without its GLSL`);
  const header = glslHeader(glsl, name);
  const size = [texture.width, texture.height, texture.depth];
  if (header.model !== model || header.law !== law || header.size.some((n, k) => n !== size[k]))
    throw new Error(`ganzfeld-three: the GLSL of table '${name}' is for law ${header.law} of ${header.model} on a ` +
                    `${header.size.join('x')} texture, but the texture holds law ${law} of ${model}, ${size.join('x')}; ` +
                    'allowed: the .glsl and .ktx2 that one export-glsl (or one /api/glsl and /api/table) wrote');
  const functionName = glslIdentifier(`${model}_${law}`);
  const sampler = is3d ? 'sampler3D' : 'sampler2D';
  if (!glsl.includes(`float ${functionName}(highp ${sampler} table,`))
    throw new Error(`ganzfeld-three: the GLSL of table '${name}' has no function ${functionName}`);
  return {
    name, model, law, formatVersion, ...ggx, lookupError,
    nodeError: Number(kv['ganzfeld.max_error'] ?? NaN),
    command: kv['ganzfeld.command'] ?? '',
    width: texture.width, height: texture.height, depth: texture.depth, texels: texture.texels,
    glsl, functionName, sampler,
    filter: kv['ganzfeld.filter'] ?? 'texel-fetch',
  };
}

/// GET `url` as an ArrayBuffer or text; an HTTP error throws an Error naming the table, the status
/// and the service's one-line {"error"} when there is one; a 503 (the service's bake queue is full)
/// is retried after its Retry-After, up to `retries` times.
export async function fetchChecked(url, as, what, retries = 30) {
  for (let attempt = 0; ; ++attempt) {
    let response;
    try {
      response = await fetch(url);
    } catch (error) {
      throw new Error(`ganzfeld-three: cannot fetch ${what} '${url}': ${error.message}`);
    }
    if (response.ok) return as === 'text' ? response.text() : response.arrayBuffer();
    if (response.status === 503 && attempt < retries) {
      const seconds = Number(response.headers.get('Retry-After')) || 1;
      await new Promise((resolve) => setTimeout(resolve, seconds * 1000));
      continue;
    }
    let message = await response.text();
    try { message = JSON.parse(message).error ?? message; } catch { /* not JSON: the text itself */ }
    throw new Error(`ganzfeld-three: ${what} '${url}': HTTP ${response.status}${message ? `: ${message.trim()}` : ''}`);
  }
}

/// A table from the two files `ganzfeld export-glsl` writes side by side (NAME.glsl, NAME.ktx2).
export async function loadTableFiles(glslUrl, ktx2Url) {
  const [glsl, bytes] = await Promise.all([fetchChecked(glslUrl, 'text', 'table GLSL'),
                                           fetchChecked(ktx2Url, 'bytes', 'table')]);
  return makeTable(bytes, glsl, String(ktx2Url));
}
