// The KTX2 files `ganzfeld export-glsl` and `ganzfeld serve` (/api/table?format=ktx2) write:
// export/texture_file.h, docs/shaders.md ("Texture files"). Khronos KTX 2.0, little-endian: the
// 12-byte identifier, nine uint32 header fields, the index (dfd, kvd offsets and lengths, sgd),
// one level index entry (offset, length, uncompressed length; uint64 each), key/value data, and
// the level's texels, x fastest, then y, then z. One channel:
//   VK_FORMAT_R32_SFLOAT (100)  float tables, 4 bytes a texel
//   VK_FORMAT_R16_SFLOAT (76)   half tables, IEEE half bits
//   VK_FORMAT_R16_UNORM  (70)   unorm16 tables, 16-bit codes; a GPU reads code / 65535 (the exported
//                               GLSL adds the table's offset and scale itself)
// readKtx2 returns the texels as a GPU reads them, as floats: half values exactly, codes as
// code / 65535, so every table uploads as one R32F texture.

const kIdentifier = [0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb, 0x0d, 0x0a, 0x1a, 0x0a];
const kHeaderBytes = 12 + 9 * 4 + 4 * 4 + 2 * 8;  // identifier, header, index
const kLevelIndexBytes = 3 * 8;
export const kVkFormatR16Unorm = 70;
export const kVkFormatR16Sfloat = 76;
export const kVkFormatR32Sfloat = 100;
const kMaxSide = 1 << 16;  // export/texture_file.cpp's reader refuses larger sides too

/// IEEE half bits to a number (exact).
function halfToFloat(bits) {
  const sign = bits & 0x8000 ? -1 : 1;
  const exponent = (bits >> 10) & 0x1f, mantissa = bits & 0x3ff;
  if (exponent === 0) return sign * mantissa * 2 ** -24;
  if (exponent === 31) return mantissa ? NaN : sign * Infinity;
  return sign * (1 + mantissa / 1024) * 2 ** (exponent - 15);
}

/// Parses `bytes` (an ArrayBuffer or a typed array) of the KTX2 file `name` (named in errors):
/// {vkFormat, width, height, depth, texels: Float32Array, keyValues: {key: text}}. Throws an Error
/// naming the file and the first problem for anything export-glsl does not write.
export function readKtx2(bytes, name) {
  const buffer = bytes instanceof ArrayBuffer ? bytes : bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const view = new DataView(buffer);
  const fail = (why) => new Error(`ganzfeld-three: '${name}' is not a ganzfeld KTX2 table: ${why}`);
  if (buffer.byteLength < kHeaderBytes + kLevelIndexBytes || kIdentifier.some((b, k) => view.getUint8(k) !== b))
    throw fail('no KTX 2.0 identifier');
  const u32 = (at) => view.getUint32(at, true);
  const u64 = (at) => u32(at) + u32(at + 4) * 2 ** 32;
  const vkFormat = u32(12), typeSize = u32(16);
  const formats = {[kVkFormatR32Sfloat]: 4, [kVkFormatR16Sfloat]: 2, [kVkFormatR16Unorm]: 2};
  if (formats[vkFormat] !== typeSize)
    throw fail(`vkFormat ${vkFormat} with typeSize ${typeSize}; allowed: 100 (R32_SFLOAT, 4), 76 (R16_SFLOAT, 2), ` +
               '70 (R16_UNORM, 2)');
  const width = u32(20), height = u32(24), depthField = u32(28);
  if (u32(32) !== 0 || u32(36) !== 1 || u32(40) !== 1 || u32(44) !== 0)
    throw fail('layers, faces, levels or supercompression other than 0, 1, 1, none');
  if (width === 0 || height === 0 || width > kMaxSide || height > kMaxSide || depthField > kMaxSide)
    throw fail(`bad dimensions ${width}x${height}x${depthField}`);
  const depth = depthField === 0 ? 1 : depthField;
  const kvdAt = u32(56), kvdLength = u32(60);
  const levelAt = u64(kHeaderBytes), levelLength = u64(kHeaderBytes + 8);
  const count = width * height * depth;
  if (levelLength !== count * typeSize || levelAt > buffer.byteLength || buffer.byteLength - levelAt < levelLength)
    throw fail(`level data of ${levelLength} bytes at ${levelAt} does not hold ${count} texels in a file of ` +
               `${buffer.byteLength} bytes`);
  if (kvdAt > buffer.byteLength || buffer.byteLength - kvdAt < kvdLength) throw fail('key/value data outside the file');
  const keyValues = {};
  const decoder = new TextDecoder();
  for (let at = kvdAt; at + 4 <= kvdAt + kvdLength;) {
    const length = u32(at);
    if (length > kvdAt + kvdLength - at - 4) throw fail('truncated key/value entry');
    const entry = new Uint8Array(buffer, at + 4, length);
    const zero = entry.indexOf(0);
    if (zero < 0) throw fail('key without terminating NUL');
    let end = length;
    if (end > zero + 1 && entry[end - 1] === 0) --end;
    keyValues[decoder.decode(entry.subarray(0, zero))] = decoder.decode(entry.subarray(zero + 1, end));
    at += 4 + ((length + 3) & ~3);
  }
  const texels = new Float32Array(count);
  for (let k = 0; k < count; ++k) {
    if (typeSize === 4) {
      texels[k] = view.getFloat32(levelAt + 4 * k, true);
      continue;
    }
    const bits = view.getUint16(levelAt + 2 * k, true);
    texels[k] = vkFormat === kVkFormatR16Unorm ? bits / 65535 : halfToFloat(bits);
  }
  return {vkFormat, width, height, depth, texels, keyValues};
}
