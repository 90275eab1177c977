#include "models/mass_hints.h"

#include <algorithm>
#include <utility>

#include "models/model.h"

namespace ganzfeld {

HintBuilder& HintBuilder::lobe(const Vec3& direction, double width, double across) {
  hints_.peaks.push_back({direction, width, across});
  return *this;
}

HintBuilder& HintBuilder::layer(double thickness) {
  if (!(thickness > 0.0 && thickness < hint_rules::kThinLayer)) return *this;  // none, or smooth on the grid's scale
  std::vector<double>& thicker = hints_.thicker_layers;
  if (thickness == hints_.horizon_layer || std::find(thicker.begin(), thicker.end(), thickness) != thicker.end())
    return *this;
  if (hints_.horizon_layer > 0.0) thicker.push_back(std::max(hints_.horizon_layer, thickness));
  hints_.horizon_layer = hints_.horizon_layer > 0.0 ? std::min(hints_.horizon_layer, thickness) : thickness;
  std::sort(thicker.begin(), thicker.end());
  return *this;
}

HintBuilder& HintBuilder::layer_where_lobe_meets_horizon(double elevation, double width, double thickness) {
  using namespace hint_rules;
  if (elevation < kReachWidths * width + kHorizonMargin)
    layer(thickness > 0.0 ? thickness : std::max(width, kThinnestLobeLayer));
  return *this;
}

HintBuilder& HintBuilder::halfway_lobe(const Vec3& fixed, double width) {
  const double across = fixed.z > 0.0 && fixed.z < hint_rules::kThinArcView ? width * fixed.z : 0.0;
  return lobe(mirror(fixed), width, across).layer_where_lobe_meets_horizon(fixed.z, width);
}

HintBuilder& HintBuilder::rough_horizon(bool rough) {
  hints_.rough_horizon = hints_.rough_horizon || rough;
  return *this;
}

HintBuilder& HintBuilder::creases(const Vec3& axis, std::vector<double> longitudes) {
  hints_.crease_axis = axis;
  hints_.crease_longitudes = std::move(longitudes);
  return *this;
}

HintBuilder& HintBuilder::merge(const MassHints& other) {
  hints_.peaks.insert(hints_.peaks.end(), other.peaks.begin(), other.peaks.end());
  layer(other.horizon_layer);
  for (double thickness : other.thicker_layers) layer(thickness);
  rough_horizon(other.rough_horizon);
  const Vec3 none{0.0, 0.0, 0.0};
  if (other.crease_axis != none && (hints_.crease_axis == none || hints_.crease_axis == other.crease_axis)) {
    hints_.crease_axis = other.crease_axis;
    hints_.crease_longitudes.insert(hints_.crease_longitudes.end(), other.crease_longitudes.begin(),
                                    other.crease_longitudes.end());
  }
  return *this;
}

}  // namespace ganzfeld
