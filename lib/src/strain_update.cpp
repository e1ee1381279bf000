// SPDX-License-Identifier: BSD-3-Clause
// The simulation's strain update (scheme.hpp, MaterialStrainUpdate): F from the grid velocities,
// then each particle's stress by its material, with the parts' strain hooks around them (shock
// physics, the thermal couplings of heat transport, the J2 return: lib/src/parts).
#include "sparsempm/scheme.hpp"

#include "sparsempm/stages.hpp"

namespace smpm {

void MaterialStrainUpdate::update(const ParticleOperators& op, const Field& v, double dt,
                                  ParticleFields& fields) {
  StrainStep s{materials_, material_, fields, dt, couplings_, density_};
  for (StageHooks* h : hooks_)
    h->before_deformation(s);
  update_deformation(op, v, dt, kind_, fields.F); // L, F, det F > 0
  for (StageHooks* h : hooks_)
    h->after_deformation(s);
  const ThermalStrainState* thermal = couplings_.thermal;
  update_stress(materials_, material_, fields.F, fields.stress, density_,
                thermal ? thermal->temperature : nullptr);
  for (StageHooks* h : hooks_)
    h->after_stress(s);
}

} // namespace smpm
