"""Elastic-perfectly-plastic normal contact: the pressure limit from the yield stress.

The exact normal solver (:class:`railcontact.normal.exact.ExactNormalModel`,
option ``pressure_limit``) bounds the pressure by a limit p_lim: every element
carries 0 <= p <= p_lim; where p reaches p_lim the surfaces may overlap (the
softer body flows plastically under the element), elsewhere the elastic
conditions hold (Kalker's problem with the pressure bounded from above, solved
by Polonsky & Keer's constrained conjugate gradients with a box constraint; the
same elastic-perfectly-plastic surface model as Jacq et al., J. Tribol. 124,
2002, without hardening).  The tangential solution then runs on the bounded
pressure, so the friction bound mu p is bounded as well.

Choice of the limit
-------------------
The bound stands for the fully plastic mean contact pressure, the *hardness* of
the softer body: ``p_lim = hardness_factor x yield_stress`` with Tabor's factor
3 (Tabor, *The Hardness of Metals*, 1951; Johnson, *Contact Mechanics*, 1985,
section 6.2: a rigid-perfectly-plastic indentation carries about 2.8-3.0 Y).  It
is CONTACT's elastic-perfectly-plastic interface model (its option M = 4 with
k_tau = 0, which bounds the *tangential* traction by the layer's yield limit
tau_c) applied to the normal pressure.  Two other limits a user may prefer, by
``pressure_factor``:

* first yield below the surface: p0 = 1.6 Y (Johnson, Table 6.1, Tresca/von Mises
  for a sphere, nu = 0.3): the pressure is then held at the elastic limit;
* the shakedown limit of repeated rolling, p0 = 4 k ~ 2.3 Y (Johnson, ch. 9).

What the bound leaves out: hardening (Mn13 crossing steel hardens strongly), the
subsurface plastic zone's own compliance (it spreads the load further than a
cap on the surface pressure, so the area is underestimated and the approach
slightly so), the residual shape of the plastically flattened surface, and large
deformations.
"""

from __future__ import annotations

import math

from ..core.errors import InputError

#: Tabor's hardness factor: the fully plastic mean pressure over the yield stress
HARDNESS_FACTOR = 3.0


def pressure_limit(yield_stress: float, pressure_factor: float = HARDNESS_FACTOR) -> float:
    """The pressure limit [Pa] of elastic-perfectly-plastic contact:
    ``pressure_factor`` x ``yield_stress`` (default Tabor's 3, see the module
    notes).

    Parameters
    ----------
    yield_stress : float
        Uniaxial yield stress Y [Pa] of the softer body (Mn13 crossing steel: 360 MPa).
    pressure_factor : float
        p_lim / Y [-]: 3 (hardness, default), 1.6 (first yield), 2.3 (shakedown).
    """
    if isinstance(yield_stress, bool) or not (isinstance(yield_stress, (int, float))
                                              and math.isfinite(yield_stress)
                                              and 1e6 <= yield_stress <= 1e11):
        raise InputError(f"plasticity.yield_stress = {yield_stress!r}: expected a stress in "
                         "Pa between 1e6 and 1e11 (Mn13 crossing steel: 3.6e8)")
    if isinstance(pressure_factor, bool) or not (isinstance(pressure_factor, (int, float))
                                                 and 1.0 <= pressure_factor <= 10.0):
        raise InputError(f"plasticity.pressure_factor = {pressure_factor!r}: expected a "
                         "factor in [1, 10] (3: hardness, 1.6: first yield)")
    return float(pressure_factor) * float(yield_stress)
