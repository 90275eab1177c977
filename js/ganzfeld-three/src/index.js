// ganzfeld-three: ganzfeld's laws of vignetting (g) and darkening (h) for three.js materials
// (docs/three.md). A HemisphereLight becomes a glossy sky and ground, an AmbientLight a glossy
// Ganzfeld, for MeshStandardMaterial and MeshPhysicalMaterial:
//
//   const tables = await GanzfeldTables.fromManifest('tables/manifest.json');  // export-glsl --scene
//   tables.apply(material);                                   // for material.roughness
//   material.userData.ganzfeld.lookupError                    // {sky, ambient}: the tables' bounds
//
// Tables per roughness R are four: g and h of ggx:roughness=R,f0=0 and of ggx:roughness=R,f0=1
// (./material.js says why). They come from the files `ganzfeld export-glsl` writes (a .glsl and a
// .ktx2 per table) or from `ganzfeld serve` (/api/table?format=ktx2 and /api/glsl).
import {fetchChecked, kRoughnessTolerance, loadTableFiles, makeTable} from './table.js';
import {checkMaterial, installGanzfeld, removeGanzfeld} from './material.js';

export {makeTable, loadTableFiles, glslIdentifier, parseGgxSpec, kFormatVersions, kLaws} from './table.js';
export {readKtx2} from './ktx2.js';
export {checkMaterial, ganzfeldLightsChunk, ganzfeldParsChunk, kDiffuseModes, kUnsupportedLayers, removeGanzfeld,
        tableTexture} from './material.js';
export {toGanzfeldScene} from './scene.js';

const kSetKeys = [['g0', 'g', 0], ['g1', 'g', 1], ['h0', 'h', 0], ['h1', 'h', 1]];

/// The spec of the table that holds law `law` of GGX at roughness R and f0 (0 or 1).
export const ggxSpec = (roughness, f0) => `ggx:roughness=${roughness},f0=${f0}`;

/// Tables of ggx by roughness; `source` names where they came from in every error.
export class GanzfeldTables {
  constructor(tables, source) {
    this.tables = tables;
    this.source = source;
  }

  /// The tables of `manifest.json` written by `ganzfeld export-glsl --scene SCENE --out DIR`
  /// (each table's .glsl and .ktx2 beside it); tables of other model families are not this
  /// module's and are skipped.
  static async fromManifest(url) {
    const manifest = JSON.parse(await fetchChecked(url, 'text', 'manifest'));
    const base = new URL(url, globalThis.location?.href);
    const entries = (manifest.textures ?? []).filter((entry) => /^ggx[:]/.test(entry.model) || entry.model === 'ggx');
    const tables = await Promise.all(entries.map((entry) => {
      if (!entry.glsl || !entry.file)
        throw new Error(`ganzfeld-three: manifest '${url}' lists table ${entry.sampler} without its .glsl and .ktx2 ` +
                        'files; allowed: a manifest of export-glsl --scene with textures (--texture ktx2)');
      return loadTableFiles(new URL(entry.glsl, base).href, new URL(entry.file, base).href);
    }));
    return new GanzfeldTables(tables, `manifest '${url}'`);
  }

  /// The tables of files `files`, [{glsl, ktx2}, ...]: each pair what `ganzfeld export-glsl TABLE.exr
  /// -o NAME.glsl` wrote (NAME.glsl and NAME.ktx2).
  static async fromFiles(files) {
    const tables = await Promise.all(files.map((file) => loadTableFiles(file.glsl, file.ktx2)));
    return new GanzfeldTables(tables, `files ${files.map((file) => `'${file.ktx2}'`).join(', ')}`);
  }

  /// The tables of roughness values `roughness` (an array) from `ganzfeld serve` at `base`
  /// (e.g. 'http://127.0.0.1:8080'), baked there on demand: `maxError` (the service's max_error:
  /// the smallest table of that validated lookup error) or `res` (nodes: '32x32x16' for g, '128'
  /// for h, as {g, h}); neither: the service's defaults.
  static async fromService(base, {roughness, maxError, res} = {}) {
    if (!Array.isArray(roughness) || roughness.length === 0)
      throw new Error('ganzfeld-three: fromService needs {roughness: [R, ...]}; allowed: R in (0, 1]');
    for (const r of roughness)
      if (!(r > 0 && r <= 1)) throw new Error(`ganzfeld-three: roughness ${r} is not allowed; allowed: (0, 1]`);
    const accuracy = (law) => (maxError !== undefined ? `&max_error=${maxError}` : res ? `&res=${res[law]}` : '');
    const loads = [];
    for (const r of roughness)
      for (const [, law, f0] of kSetKeys) {
        const query = `model=${encodeURIComponent(ggxSpec(r, f0))}&law=${law}${accuracy(law)}`;
        const ktx2 = `${base}/api/table?${query}&format=ktx2`;
        loads.push(Promise.all([fetchChecked(`${base}/api/glsl?${query}`, 'text', 'table GLSL'),
                                fetchChecked(ktx2, 'bytes', 'table')])
          .then(([glsl, bytes]) => makeTable(bytes, glsl, ktx2)));
      }
    return new GanzfeldTables(await Promise.all(loads), `service '${base}'`);
  }

  /// The roughness values for which all four tables are present, ascending.
  get roughnessValues() {
    const values = [];
    for (const table of this.tables)
      if (!values.some((r) => Math.abs(r - table.roughness) <= kRoughnessTolerance)) values.push(table.roughness);
    return values.filter((r) => this.missing(r).length === 0).sort((a, b) => a - b);
  }

  /// Which of g0, g1, h0, h1 are missing at roughness r.
  missing(r) {
    return kSetKeys.filter(([, law, f0]) => !this.find(r, law, f0)).map(([key]) => key);
  }

  find(r, law, f0) {
    return this.tables.find((t) => t.law === law && t.f0 === f0 && Math.abs(t.roughness - r) <= kRoughnessTolerance);
  }

  /// {alpha, roughness, g0, g1, h0, h1} at roughness r, or an Error naming the tables and the
  /// roughness values they allow.
  set(r) {
    const allowed = this.roughnessValues.map((v) => Number(v.toPrecision(12))).join(', ') || 'none (no complete set)';
    if (!(typeof r === 'number' && Number.isFinite(r)))
      throw new Error(`ganzfeld-three: roughness ${r} is not a number; the tables of ${this.source} allow ${allowed}`);
    const missing = this.missing(r);
    if (missing.length === 4)
      throw new Error(`ganzfeld-three: roughness ${r} is outside the tables of ${this.source}; allowed: ${allowed} ` +
                      '(bake the tables of another roughness: docs/three.md)');
    if (missing.length > 0)
      throw new Error(`ganzfeld-three: the tables of ${this.source} at roughness ${r} lack ` +
                      `${missing.map((k) => `law ${k[0]} of ${ggxSpec(r, Number(k[1]))}`).join(', ')}; allowed: ${allowed}`);
    const set = {roughness: r};
    for (const [key, law, f0] of kSetKeys) set[key] = this.find(r, law, f0);
    set.alpha = set.g0.alpha;
    return set;
  }

  /// Makes `material` (MeshStandardMaterial or MeshPhysicalMaterial) shade its HemisphereLights
  /// and AmbientLights with the tables of its roughness. Throws, leaving the material as it was,
  /// when there are none or the material is not supported. {diffuse: 'three' | 'lambert'}: see
  /// ./material.js. Returns material.userData.ganzfeld: {roughness, diffuse, tables,
  /// lookupError: {sky, ambient}}.
  apply(material, {diffuse = 'three'} = {}) {
    checkMaterial(material);  // before the roughness: a material without one is named for what it is
    return installGanzfeld(material, this.set(material.roughness), diffuse);
  }

  /// Back to three.js's own shading of `material`.
  remove(material) {
    removeGanzfeld(material);
  }
}

/// The lookup errors of the tables `material` shades with, {sky, ambient}, or null when it does
/// not use the module.
export function ganzfeldLookupError(material) {
  return material?.userData?.ganzfeld?.lookupError ?? null;
}
