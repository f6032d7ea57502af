// The tessellations of a CAD model tried in turn when the mesher cannot go
// on with one: `vdmesh mesh` (cad_mesher.cpp) and `vdmesh compare` walk the
// same chain, so a file that meshes gets compared on the surface it meshes
// on. Needs no OpenCASCADE: the program's compare runs it without the plugin.
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <vector>

#include "cad/cad_model.h"

namespace vd::cad {

// Patience of a recovery that has another tessellation to fall back on:
// gmsh_917_fusee.stp's first two ran away (752 -> 8,428 facets missing while
// 27k vertices went in) and stopped at the guards after 11 s; the third
// tessellation meshed in 1.5 s.
constexpr int kPatienceWithAFallback = 8;
// The uniform chord heights tried again after a recovery on them stopped
// (before the other angles), as factors of the first: gmsh_simple_plane.brep
// at size 0.35 stopped on the size / 500 of every face (77 facets of a wing
// root left after 59 passes) and ran away on the other angles (exit 4 after
// 198 s), and meshed at size / 1000 (so did 0.32, 0.38, 0.4 and 0.45, in 5.5
// to 12.5 s). Halved twice only, it still ended in exit 4 at 5 of 10 sizes
// between 0.30 and 0.43 (2026-11-28): where its wing's skins meet at small
// angles, the splits of recovery stall or run away, and which chord heights
// get through moves with them chaotically (0.32 and 0.320008 meshed,
// 0.3200076 did not), so two more heights between the halvings give it two
// more chances.
constexpr double kUniformChordRetries[] = {0.5, 0.25, 0.75, 0.375};

class TessellationChain {
 public:
  // `first`: the first tessellation's options. `retry_angles_deg`: the
  // angular deflections tried after it when recovery stops, on automatic
  // chord heights only. `uniform_deflection` > 0: before them, one at the
  // first angle starting from this chord height on every face (the volume
  // rounds refine the solids that are off from there).
  TessellationChain(const TessellationOptions& first, const std::vector<double>& retry_angles_deg,
                    double uniform_deflection)
      : first_(first), options_(first), angles_{first.angle_deg} {
    if (first.deflection == 0) angles_.insert(angles_.end(), retry_angles_deg.begin(), retry_angles_deg.end());
    uniform_deflection_ = !retry_angles_deg.empty() && first.deflection == 0 ? uniform_deflection : 0;
  }

  const TessellationOptions& options() const { return options_; }
  // Tessellations given up so far.
  int attempt() const { return attempt_; }
  // The current tessellation is the one with uniform chord heights.
  bool on_uniform_chords() const { return uniform_; }
  // The uniform chord heights were tried (now, or before a later angle).
  bool uniform_tried() const { return uniform_tried_; }
  // Another tessellation follows if recovery stops on this one (its
  // patience is kPatienceWithAFallback). Not on the uniform chords, though
  // the other angles may follow them: they are the link that meshes thin
  // solids (gmsh_simple_plane.brep: 49 passes), and keep the full patience.
  bool has_fallback() const {
    return !uniform_ && (options_.smooth || options_.remesh || (uniform_deflection_ > 0 && !uniform_tried_) ||
                         angle_ + 1 < angles_.size());
  }

  // The next tessellation after one that failed: its recovery stopped at the
  // guards, or (false) its surface was refused. In turn: the first one
  // unsmoothed and not remeshed at the same angle (on gmsh_dlr_f6.brep the
  // smoothed 20 deg surface stopped recovery and the smoothed 30 deg one
  // crossed itself; the surface itself is fine unsmoothed), then the
  // uniform chord heights at the first angle, then the other angles
  // unsmoothed. The uniform chords came after the other angles until
  // 2026-11-27: on the corpus no file meshes at 30 or 40 deg any more, and
  // gmsh_simple_plane.brep spent 5 s on them before the uniform chords
  // meshed it (the same mesh either way). False: nothing left to try.
  // `runaway_faces`: the face numbers of the facets the stopped recovery
  // left missing, ascending. The faces where every stopped recovery before
  // them ran away go to the uniform chords' volume rounds, which leave
  // their solids alone: on gmsh_simple_plane.brep the union of the
  // recoveries' faces took in the tail, 5.9 % off, whose facets one of
  // them had left. `ran_away`: the stopped recovery ran away (its missing
  // facets grew far past where they started). Then the unsmoothed surface,
  // which has the same chord heights, is skipped for the uniform chords:
  // on the corpus only gmsh_simple_plane.brep's first recovery runs away,
  // at its thin walls, and its unsmoothed surface stopped too (2.5 s, the
  // same faces held and the same mesh after it); the ellipses' unsmoothed
  // surface, which meshed, came after a recovery that only stalled (until
  // the border caps were snapped, 2026-11-27: now their first one meshes).
  bool next(bool recovery_stopped, const std::vector<int>& runaway_faces = {}, bool ran_away = false) {
    if (recovery_stopped) {
      if (stopped_recoveries_++ == 0) {
        runaway_faces_ = runaway_faces;
      } else {
        std::vector<int> both;
        std::set_intersection(runaway_faces_.begin(), runaway_faces_.end(), runaway_faces.begin(),
                              runaway_faces.end(), std::back_inserter(both));
        runaway_faces_ = std::move(both);
      }
    }
    if (uniform_ && recovery_stopped && retries_ < std::size(kUniformChordRetries)) {
      // Thin solids need finer chords than the size's share (above).
      options_.start_deflection = uniform_deflection_ * kUniformChordRetries[retries_++];
      options_.runaway_faces = runaway_faces_;
      ++attempt_;
      return true;
    }
    if (uniform_) {
      // Whatever else stopped the uniform chords, the other angles follow,
      // with automatic chord heights again.
      if (angle_ + 1 >= angles_.size()) return false;
      uniform_ = false;
      options_.smooth = options_.remesh = false;
      options_.start_deflection = first_.start_deflection;
      options_.runaway_faces.clear();
      ++angle_;
    } else if ((options_.smooth || options_.remesh) && !(ran_away && uniform_deflection_ > 0)) {
      options_.smooth = options_.remesh = false;
    } else if (!recovery_stopped) {
      return false;
    } else if (uniform_deflection_ > 0 && !uniform_tried_) {
      options_.smooth = first_.smooth;
      options_.remesh = first_.remesh;
      options_.start_deflection = uniform_deflection_;
      options_.runaway_faces = runaway_faces_;
      uniform_ = uniform_tried_ = true;
    } else if (angle_ + 1 < angles_.size()) {
      ++angle_;
    } else {
      return false;
    }
    options_.angle_deg = angles_[angle_];
    ++attempt_;
    return true;
  }

 private:
  TessellationOptions first_, options_;
  std::vector<double> angles_;
  std::vector<int> runaway_faces_;  // in every stopped recovery so far
  int stopped_recoveries_ = 0;
  size_t retries_ = 0;  // of the uniform chord heights (kUniformChordRetries)
  double uniform_deflection_ = 0;
  size_t angle_ = 0;
  int attempt_ = 0;
  bool uniform_ = false;        // the current tessellation has the uniform chords
  bool uniform_tried_ = false;  // they were tried
};

}  // namespace vd::cad
