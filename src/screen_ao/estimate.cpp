#include "screen_ao/estimate.h"

namespace gtbake {

AoEstimate makeEstimate(const GBuffer& g, EstimateParts parts) {
  AoEstimate e;
  e.a.assign(g.pixels(), 0.0f);
  if (parts == EstimateParts::kAoAndBent) e.bent.assign(3 * g.pixels(), 0.0f);
  return e;
}

}  // namespace gtbake
