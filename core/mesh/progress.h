// How far the running phase has got, for a display on a terminal: the long
// loops (insertion into the tetrahedralization, the interior lattice,
// recovery passes, sliver passes) set a fraction, a display thread reads it.
// One value per process, the last writer wins: it is for showing, never for
// deciding anything, so runs on several threads at once only blur the display.
#pragma once

namespace vd {

// done in [0, 1].
void set_phase_fraction(double done);
// The phase has not said (each phase starts so).
void clear_phase_fraction();
// The last fraction set, or < 0 when none was since the clear.
double phase_fraction();

}  // namespace vd
