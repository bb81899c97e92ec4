// Style as a difference in harmonic space between two clips of the same action and skeleton
// (neutral and styled, strides aligned): per joint a posture offset, per channel a mean offset and
// per harmonic an amplitude ratio and phase shift, plus tempo and speed ratios. Applying a style
// with weight w: 0 changes nothing, 1 gives the styled clip's character, > 1 exaggerates, < 0
// removes. Styles measured on one clip transfer to any clip of the same skeleton.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::spectral {

struct HarmonicStyle {
  int n = 1;                  // harmonic number
  double log_ratio = 0.0;     // ln(B_styled / B_neutral), clamped to +-ln 8
  double phase_shift = 0.0;   // D_styled - D_neutral, radians in (-pi, pi]
};

struct ChannelStyle {
  int joint = 0;
  SignalKind kind = SignalKind::kRotation;
  int axis = 0;
  double mean_offset = 0.0;            // A_styled - A_neutral (after the posture offset)
  std::vector<HarmonicStyle> harmonics;
};

struct StyleVector {
  std::string label;                   // "tired", "happy", ...
  int joint_count = 0;                 // the skeleton it was measured on
  double log_tempo = 0.0;              // ln(omega_styled / omega_neutral)
  double log_speed = 0.0;              // ln(|travel_styled| / |travel_neutral|), 0 when in place
  std::vector<glm::dvec3> posture;     // (joints) rotation vector of neutral^-1 * styled base
  std::vector<ChannelStyle> channels;
};

// Puts the phase origin where `joint`'s `axis` rotation channel's fundamental has phase 0, so
// clips of one skeleton start their strides at the same gait event.
void alignPhase(TargetMotion& target, int joint, int axis);
// The rotation channel with the largest fundamental: the one to align clips of a skeleton on.
std::pair<int, int> phaseReference(const TargetMotion& target);

// The style taking `neutral` to `styled` (same skeleton; both aligned with alignPhase on the same
// channel). Harmonics too weak in the neutral (under 2% of its channel's strongest) keep ratio 1.
Result<StyleVector> measureStyle(const TargetMotion& neutral, const TargetMotion& styled,
                                 const std::string& label);

// `target` with every style applied at its weight (weights add in log space), w in [-1, 2].
Result<TargetMotion> applyStyles(const TargetMotion& target,
                                 const std::vector<std::pair<const StyleVector*, double>>& styles);

// The joints whose posture tells a style across actions, the body's carriage: the trunk (spine
// joints below the pelvis) and the neck, and each limb's proximal part, from its root down to
// its first long bone (at least a quarter of the limb: clavicle and upper arm, hip and thigh).
// Left out: joints above the pelvis (they carry the global heading: where the actor went, not
// how), the head (it turns to keep the gaze where the action needs it: running lifts it 15
// degrees against the neck whatever the mood, and the tired walk's flexed neck is compensated by
// a head lifted 5 degrees), and the distal joints (elbows, knees, hands, feet), which the action's
// mechanics set: running bends the elbows 40 degrees, as much as the angry walk does.
// Skeleton order.
std::vector<int> carriageJoints(const motion::Skeleton& skeleton);

// OK when `other` has `reference`'s joints by name and hierarchy (same names in the same order,
// same parents); otherwise names the first joint that differs. A style measured on one skeleton
// means nothing on another with the same joint count.
Status sameJoints(const motion::Skeleton& reference, const motion::Skeleton& other);

// Style measurement. Scores in [0, 1], one per label (several library entries may share a label:
// they are examples of it, and the nearest one counts), summing to 1.
struct StyleScores {
  std::string closest;
  std::vector<std::pair<std::string, double>> scores;  // label -> score, in first-seen order
  std::vector<double> distances;  // (labels) the nearest example's distance, in the units the
                                  // Gaussian is 1 wide (see scoreStyle and scoreStyleRelative)
  std::vector<int> examples;      // (labels) library entries with that label
};

// Absolute: how close `clip` is to each labelled library clip (clips of one skeleton) in what a
// style changes and an action does not: the posture of the carriage joints (each one's mean
// rotation, relative to the library's mean), compared as RMS angles; a Gaussian of the RMS
// angle, 5 degrees wide (distances in units of 5 degrees), normalised.
Result<StyleScores> scoreStyle(const motion::Skeleton& skeleton, const TargetMotion& clip,
                               const std::vector<std::pair<std::string, TargetMotion>>& library);

// A library entry measured relative to its own actor's neutral (same action, same skeleton).
struct StyleExample {
  std::string label;
  TargetMotion neutral;
  TargetMotion styled;
};

// What a style changes, relative to a neutral of the same actor and action: the carriage
// joints' posture change (rotation vectors, radians), each moving joint's change of amplitude
// (log ratio of its rotation harmonics' root-sum-square amplitude; a joint under 0.02 rad in the
// neutral counts from 0.02) and the tempo change (log ratio). Differences between actors (their
// proportions, their own carriage and swing) cancel.
struct RelativeStyle {
  std::vector<double> posture;    // (3 x carriage joints) radians
  std::vector<double> amplitude;  // (joints below the pelvis) log ratios
  double log_tempo = 0.0;
};
RelativeStyle relativeStyle(const motion::Skeleton& skeleton, const TargetMotion& neutral,
                            const TargetMotion& styled);

// Relative: `clip`'s style against `neutral` (same actor) compared with each example's against
// its own neutral. The distance combines, each scaled to a just-visible change and then RMS'd
// over the three parts: the posture RMS over 5 degrees, the amplitude RMS over ln 1.25, and the
// tempo over ln 1.1; the score is a Gaussian of it, 1 wide, normalised over the labels.
Result<StyleScores> scoreStyleRelative(const motion::Skeleton& skeleton, const TargetMotion& clip,
                                       const TargetMotion& neutral,
                                       const std::vector<StyleExample>& library);

// How much of a pair's style `clip` carries: the projection of clip's style relative to `neutral`
// (relativeStyle) on the pair's (`styled` against `neutral`), each part scaled as
// scoreStyleRelative scales it. 0: the neutral's, 1: the styled clip's, > 1 exaggerated, < 0
// the opposite way. A pair with no difference gives 0.
double styleAmount(const motion::Skeleton& skeleton, const TargetMotion& clip,
                   const TargetMotion& neutral, const TargetMotion& styled);

// Style distance in harmonic space between a recorded run and the target it tracked: each of the
// target's rotation channels is measured in the run (the joint's rotation relative to the
// target's base, as a rotation vector) over the whole periods of `omega` (rad/s, > 0) after
// `skip_s` seconds: its mean and the amplitude of each of the channel's harmonics. Per joint
// group (legs, arms, spine, head) the RMS over the group's channels of the distance between those
// and the target's (means and amplitudes; phases left out, so a run late by a few frames is not a
// different style), then the mean over the groups present. Radians. A run shorter than one period
// after the skip counts as still (every amplitude 0, its mean pose over what there is; a run of
// fewer than two frames, still at the target's base).
double runStyleDistance(const motion::Skeleton& skeleton, const motion::Clip& run,
                        const TargetMotion& target, double omega, double skip_s);

}  // namespace sinew::spectral
