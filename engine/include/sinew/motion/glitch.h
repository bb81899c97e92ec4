// Glitches in captured rotations: a joint that jumps away for one to a few frames and comes back
// (a toe turning 180 degrees about one axis, a spike from a marker swap), far from both of its
// neighbours while they agree with each other. Found per joint and repaired by interpolation
// between the good neighbours, before anything analyses the clip.
//
// What makes a glitch, rather than fast true motion, is measured against the joint's own motion:
// the excursion (the largest angle between a frame and the slerp across the run) must be many
// times the joint's typical frame-to-frame step, the jumps into and out of the run must both be
// that large, and the frames either side must be closer to each other than the run is to them. A
// heel strike or a flicking tail reverses within one frame at most by its own step, which is what
// the typical step already measures (at the clip's frame rate); a flip does not come from there.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"

namespace sinew::motion {

struct GlitchSettings {
  double relative_size = 6.0;     // an excursion must exceed this many times the joint's typical
                                  // step (step_quantile of its frame-to-frame rotation angles), > 0
  double step_quantile = 0.9;     // which quantile of the joint's steps is its typical step, 0..1;
                                  // high enough that fast phases count, low enough that a few
                                  // glitch frames do not move it
  double min_size_deg = 10.0;     // and exceed this angle, degrees, > 0: a still joint's sensor
                                  // noise is tiny, and so is its typical step
  double max_duration_s = 0.125;  // longest run of glitch frames, seconds (at least one frame at
                                  // any frame rate; 3 at 24 and 30 fps, 15 at 120), > 0; longer
                                  // departures are motion
  double max_across_ratio = 0.5;  // the frames either side of the run are at most this fraction
                                  // of the excursion apart, >= 0: the run left and came back

  Status validate() const;  // the message names the offending field
};

struct Glitch {
  int joint = 0;          // skeleton joint index
  int first_frame = 0;    // first bad frame; first_frame - 1 is good, and first_frame >= 1
  int frame_count = 0;    // bad frames, >= 1; first_frame + frame_count is good and in the clip
  double size_deg = 0.0;  // largest angle between a bad frame and its repair, degrees
};

// Glitches in the clip's joint rotations, by joint then frame; runs do not overlap. The first and
// last frames are never called glitches (they have one neighbour). Precondition: settings valid,
// clip validated.
std::vector<Glitch> findGlitches(const Clip& clip, const GlitchSettings& settings = {});

// Replaces each glitch's frames from its good neighbours: a cubic through two good frames each
// side (in rotation vectors relative to the frame before), or the slerp (the short way) between
// the one frame each side near the clip's ends; or, when the motion repeats, the same frames a
// stride away (the lag, 0.25-2.5 s, at which the 0.2 s of good frames either side best match
// themselves), carried onto the glitch's boundary frames. The stride is used where it recovers
// pretend runs of the same length among those good frames better than the cubic does: a toe-off
// snap no interpolation sees is in the previous stride. Only those frames and joints change.
void repairGlitches(Clip& clip, std::span<const Glitch> glitches);

// "Toe_L frames 120-122 (3): 180.0 deg" (frames counted from 0, as everywhere in Sinew).
std::string describeGlitch(const Skeleton& skeleton, const Glitch& glitch);

}  // namespace sinew::motion
