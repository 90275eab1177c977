/* An engine's use of `ganzfeld export-glsl --texture header`: the exported C header compiled in
 * (as C11 and as C++17: tests/header_export_test.sh) and sampled on the CPU with the lookup the
 * header's comment names, a cosines-frame table blended linearly (docs/lut-format.md, "Sampling"):
 * per axis t = clamp((x - min) / (max - min), 0, 1), u = t, sqrt(t) or acos(1 - 2t) / pi by the
 * axis' mapping, s = u (count - 1), k = min(floor(s), count - 2), and the multilinear blend of the
 * nodes around it. Texels are decoded as the header says: floats, IEEE half bits, or unorm16 codes
 * with value = (float)(offset + scale x code / 65535).
 *
 * Build: -DGZ_HEADER='"path.h"' -DGZ_SYMBOL=name [-DGZ_HALF | -DGZ_UNORM16].
 * Run:   header_lookup LAW POINTS SEED then per axis, slowest first: MAPPING MIN MAX
 * Prints per point "[--i x,y,z] --j x,y,z value" (directions in the local frame, n = +z; %.17g;
 * --i for g only), for `ganzfeld sample` to look up the same point. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include GZ_HEADER

#define GZ_CAT(a, b) a##b
#define GZ_NAME(symbol, suffix) GZ_CAT(symbol, suffix)
#define GZ_TEXELS GZ_NAME(GZ_SYMBOL, _texels)

static const double kPi = 3.14159265358979323846;

#ifdef GZ_HALF
/* IEEE binary16 to double, exactly (no infinities or NaNs in a table). */
static double half_to_double(uint16_t bits) {
  const int exponent = (bits >> 10) & 31, mantissa = bits & 1023;
  const double magnitude = exponent == 0 ? ldexp((double)mantissa, -24) : ldexp((double)(mantissa | 1024), exponent - 25);
  return (bits & 0x8000) ? -magnitude : magnitude;
}
#endif

static double texel(long k) {
#if defined(GZ_UNORM16)
  return (float)((double)GZ_NAME(GZ_SYMBOL, _unorm16_offset) +
                 (double)GZ_NAME(GZ_SYMBOL, _unorm16_scale) * (GZ_TEXELS[k] / 65535.0));
#elif defined(GZ_HALF)
  return half_to_double(GZ_TEXELS[k]);
#else
  return GZ_TEXELS[k];
#endif
}

struct axis {
  const char* mapping;
  double min, max;
  int count;
};

/* The lower node k and the fraction t of coordinate x on an axis. */
static void cell(const struct axis* a, double x, int* k, double* t) {
  double u = (x - a->min) / (a->max - a->min);
  u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
  if (strcmp(a->mapping, "sqrt") == 0) u = sqrt(u);
  else if (strcmp(a->mapping, "cos") == 0) u = acos(1.0 - 2.0 * u) / kPi;
  else if (strcmp(a->mapping, "linear") != 0) {
    fprintf(stderr, "header_lookup: mapping '%s' is not one of linear, sqrt, cos\n", a->mapping);
    exit(2);
  }
  const double s = u * (a->count - 1);
  *k = (int)floor(s) < a->count - 2 ? (int)floor(s) : a->count - 2;
  *t = s - *k;
}

/* A uniform pseudo-random number in [0, 1) (64-bit LCG, Knuth's MMIX constants). */
static double uniform(uint64_t* state) {
  *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*state >> 11) / 9007199254740992.0;
}

int main(int argc, char** argv) {
  if (argc < 4) {
    fprintf(stderr, "usage: header_lookup g|h POINTS SEED (MAPPING MIN MAX)...\n");
    return 2;
  }
  const int g = strcmp(argv[1], "g") == 0, dims = g ? 3 : 1;
  const int points = atoi(argv[2]);
  uint64_t state = strtoull(argv[3], NULL, 10);
  if (argc != 4 + 3 * dims) {
    fprintf(stderr, "header_lookup: law %s needs %d axes\n", argv[1], dims);
    return 2;
  }
  /* The header's dimensions: width = fastest axis (the last), depth = slowest (g). */
  const int counts[3] = {g ? GZ_NAME(GZ_SYMBOL, _depth) : GZ_NAME(GZ_SYMBOL, _width), GZ_NAME(GZ_SYMBOL, _height),
                         GZ_NAME(GZ_SYMBOL, _width)};
  struct axis axes[3];
  for (int d = 0; d < dims; ++d) {
    axes[d].mapping = argv[4 + 3 * d];
    axes[d].min = atof(argv[5 + 3 * d]);
    axes[d].max = atof(argv[6 + 3 * d]);
    axes[d].count = counts[d];
  }
  const long entries = (long)(sizeof GZ_TEXELS / sizeof GZ_TEXELS[0]);
  if (entries != (long)GZ_NAME(GZ_SYMBOL, _width) * GZ_NAME(GZ_SYMBOL, _height) * GZ_NAME(GZ_SYMBOL, _depth)) {
    fprintf(stderr, "header_lookup: %ld texels for dimensions %d x %d x %d\n", entries, GZ_NAME(GZ_SYMBOL, _width),
            GZ_NAME(GZ_SYMBOL, _height), GZ_NAME(GZ_SYMBOL, _depth));
    return 1;
  }
  for (int p = 0; p < points; ++p) {
    /* The law's coordinates: g (i.n in [-1, 1], j.n in [0, 1], phi in [0, pi]); h (j.n in [0, 1]). */
    const double ci = g ? 2.0 * uniform(&state) - 1.0 : 1.0, cj = uniform(&state), phi = g ? kPi * uniform(&state) : 0.0;
    const double x[3] = {g ? ci : cj, cj, phi};
    int k[3] = {0, 0, 0};
    double t[3] = {0.0, 0.0, 0.0};
    for (int d = 0; d < dims; ++d) cell(&axes[d], x[d], &k[d], &t[d]);
    double value = 0.0;
    if (g) {
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int c = 0; c < 2; ++c) {
            const double w = (a ? t[0] : 1.0 - t[0]) * (b ? t[1] : 1.0 - t[1]) * (c ? t[2] : 1.0 - t[2]);
            value += w * texel(((long)(k[0] + a) * counts[1] + k[1] + b) * counts[2] + k[2] + c);
          }
    } else {
      value = (1.0 - t[0]) * texel(k[0]) + t[0] * texel(k[0] + 1);
    }
    const double si = sqrt(1.0 - ci * ci), sj = sqrt(1.0 - cj * cj);
    if (g) printf("--i %.17g,0,%.17g ", si, ci);
    printf("--j %.17g,%.17g,%.17g %.17g\n", sj * cos(phi), sj * sin(phi), cj, value);
  }
  return 0;
}
