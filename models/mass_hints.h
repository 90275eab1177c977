// Where a model's integrand (k·n) f(k, fixed) [or f(fixed, k)] has its mass, in the one form the
// integrator reads (MassHints), written the one way every model writes it (HintBuilder), and the
// scales at which the engine acts on it (namespace hint_rules, read by integrate/laws_integrals.cpp).
//
// A model author states physics only: a lobe (centre and width), a horizon layer (thickness),
// a rough horizon, creases. The rules that turn these into the engine's initial grid live here
// once, so a hint is right whoever writes it; tests/hints_test.cpp judges every registered model's
// hints at its defaults and at its parameters' ends against the independent reference (reference/).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace ganzfeld {

using Vec3 = glm::dvec3;

/// A lobe of the integrand: the integrator splits panels there instead of hoping its first nodes
/// land on it (integrate/cubature.h).
struct Peak {
  Vec3 direction;  ///< unit vector of the lobe's maximum (may lie outside the domain)
  double width;    ///< angular scale in radians (e.g. sqrt(2/alpha) for a cosine-power lobe)
  /// Angular scale across the plane of n and the peak, when the lobe is elongated (0: the same
  /// as width). Halfway-vector lobes near grazing are 10^4 times thinner across than along.
  double across = 0.0;
};

struct MassHints {
  std::vector<Peak> peaks;
  /// Thickness in k·n of a layer of mass hugging the horizon (asperity lobes, the
  /// 1/((i+j)·n) factor of perfect backscatter); 0 when there is none. Of several layers the
  /// thinnest, the one the grid must resolve and grade towards.
  double horizon_layer = 0.0;
  /// The other layers, each thicker than horizon_layer (ascending): a grazing GGX lobe is a layer
  /// as thick as its width with a visibility layer as thin as j·n inside it, and a mixture holds
  /// its lobes' layers side by side. Each gets its lines as horizon_layer does.
  std::vector<double> thicker_layers{};
  /// The integrand behaves like (k·n)^nu at the horizon with a non-integer nu < 2 (Minnaert's
  /// (k·n)^(1+xi)): a weak singularity at the edge of the domain, which the integrator grades.
  bool rough_horizon = false;
  /// Half great circles from -crease_axis to +crease_axis across which the integrand jumps or
  /// kinks, given by their longitude about crease_axis: phi(k) = atan2(k·u, k·n) with
  /// u = crease_axis × n, in (-pi/2, pi/2). Poulin–Fournier's cylinder shadowing depends only on
  /// the angle of k projected on the plane perpendicular to the cylinders, so its jumps lie on
  /// such circles. The integrator then works in a frame whose meridians are these circles and
  /// cuts its panels there (integrate/laws_integrals.cpp): the jumps are resolved by splitting,
  /// not by bisecting towards them. crease_axis must be horizontal (·n = 0); zero means none.
  Vec3 crease_axis{0.0, 0.0, 0.0};
  std::vector<double> crease_longitudes{};
};

/// The engine's rules for hints, stated once. integrate/laws_integrals.cpp builds its initial grid
/// from them; HintBuilder applies the one that a model's hint depends on (a lobe reaching the
/// horizon). Each is measured on the 1,200-case peers benchmark (bench/) and the extremes grid
/// (docs/reliability-extremes.md); changing one changes every table.
namespace hint_rules {

/// A lobe (or step) wider than this, in radians, gets no lines: the 2x2 starting grid's panels,
/// pi/2 wide, resolve it by adaptivity alone.
inline constexpr double kBroadLobe = 0.35;
/// A horizon layer at least this thick gets no lines, for the same reason.
inline constexpr double kThinLayer = 0.3;
/// A lobe at least this wide gets a line at its centre only: the first Kronrod node of the panels
/// that meet there lies within 0.0043 panel widths of the line (< 0.014 rad), inside the lobe
/// (measured: 25% fewer evaluations for specular and backscatter lobes, no estimate less honest).
inline constexpr double kCentreLineOnly = 0.02;
/// Sharper lobes get lines at ±kFlankWidths widths about the centre as well (measured: 15% fewer
/// evaluations than ±1 and ±4 widths, as honest).
inline constexpr double kFlankWidths = 2.0;
/// A sharp lobe's ladder: lines at kLadderFirst, kLadderFirst·kLadderRatio, ... widths up to
/// kBroadLobe, so the panels beside it grow gradually; a hint narrower than the lobe's real tails
/// would otherwise leave them at the edge of a panel a thousand times wider, where no node looks.
inline constexpr double kLadderFirst = 16.0;
inline constexpr double kLadderRatio = 8.0;
/// Widths are floored here (radians): a line offset by less from another is within a few hundred
/// ulps of pi/2, where the bisection can no longer separate them.
inline constexpr double kNarrowestWidth = 1e-13;
/// A lobe reaches an edge of the domain (the horizon, a pole of the coordinates) when its centre
/// is within this many widths of it: beyond 4 widths a Gaussian lobe holds < 4e-4 of its peak.
inline constexpr double kReachWidths = 4.0;
/// Near a coordinate pole every longitude meets, so the part of a lobe inside the domain can be
/// far smaller than the lobe: a ladder w/8, w/64, ... ends this close to the pole (radians).
inline constexpr double kPoleLadderEnd = 1e-12;
/// A horizon layer of thickness delta gets lines at these multiples of delta from the horizon.
inline constexpr double kLayerLines[] = {1.0, 4.0};
/// Layers thinner than this (and rough horizons) are graded towards the horizon
/// (integrate/laws_integrals.cpp, Grading): measured 1.5-2.6x fewer evaluations; a 0.27 layer
/// cost 17% more graded, so thicker layers are not graded.
inline constexpr double kGradedLayer = 0.02;
/// A lobe whose centre stands less than kReachWidths widths plus this margin (radians) above the
/// horizon hugs it: whatever its width, a lobe centred within 0.05 rad (3°) of the horizon is cut
/// by it, and its mass along the horizon is a layer (tests/extremes_test.cpp,
/// PhongGrazingLayerIsHonest, GgxGrazingVisibilityLayerIsHonest).
inline constexpr double kHorizonMargin = 0.05;
/// The thinnest such layer a lobe implies: a lobe narrower than this is a layer this thick.
inline constexpr double kThinnestLobeLayer = 1e-9;
/// A microfacet lobe (HintBuilder::halfway_lobe) for a fixed direction within this j·n of the
/// horizon (about 89.9°) is a thin arc across the plane of incidence; above it the arc needs no lines
/// of its own: measured on 102 cases of GGX's a and g at 1e-9, those lines cost 43% more evaluations
/// and were no more honest.
inline constexpr double kThinArcView = 1e-3;

}  // namespace hint_rules

/// The one way a model states its hints:
///   return HintBuilder().lobe(mirror(fixed), w).layer_where_lobe_meets_horizon(fixed.z, w).build();
class HintBuilder {
 public:
  /// A lobe centred on `direction` (need not be unit or above the horizon), `width` radians wide
  /// (its scale at half maximum, about one standard deviation); `across`, when the lobe is
  /// elongated, its scale across the plane of n and the centre (0: as wide across as along).
  HintBuilder& lobe(const Vec3& direction, double width, double across = 0.0);
  /// A layer of mass hugging the horizon, `thickness` thick in k·n; of several, every one gets
  /// its lines (MassHints::thicker_layers) and the thinnest its grading. A thickness that is not > 0 declares none, and
  /// one at least hint_rules::kThinLayer neither: such a layer is smooth on the scale of the starting grid.
  HintBuilder& layer(double thickness);
  /// The layer of a lobe of `width` radians whose centre stands `elevation` above the horizon
  /// (radians, or its sine, a lower bound that declares the layer a little earlier): declared when
  /// elevation < kReachWidths·width + kHorizonMargin, `thickness` thick (by default the lobe's
  /// width, floored at kThinnestLobeLayer).
  HintBuilder& layer_where_lobe_meets_horizon(double elevation, double width, double thickness = 0.0);
  /// A microfacet lobe: the halfway vector's distribution, `width` radians wide in the angle from
  /// the mirror of `fixed`. Tilting the halfway vector by d across the plane of incidence moves the
  /// reflection by about 2 d (fixed·n), so for fixed·n < kThinArcView the lobe is an arc
  /// width·(fixed·n) across; and where it meets the horizon, a layer (layer_where_lobe_meets_horizon).
  HintBuilder& halfway_lobe(const Vec3& fixed, double width);
  /// The integrand ~ (k·n)^nu at the horizon, nu < 2 not an integer (when `rough`).
  HintBuilder& rough_horizon(bool rough = true);
  /// Creases on half great circles about the horizontal `axis` at these longitudes
  /// (MassHints::crease_axis); a zero axis declares none.
  HintBuilder& creases(const Vec3& axis, std::vector<double> longitudes);
  /// Another model's hints, as a mixture's lobe: its lobes and layer join these; one crease frame
  /// per integral, so creases about another axis than the first are left to plain adaptivity.
  HintBuilder& merge(const MassHints& other);
  MassHints build() const { return hints_; }

 private:
  MassHints hints_;
};

}  // namespace ganzfeld
