#pragma once
// How every command reads a model: what loading found wrong (core/mesh.hpp: MeshProblems, e.g.
// faces dropped for an index out of range or a NaN vertex) is never silent: one warning line on
// stderr naming the model when the command succeeds (a failing command prints its one error line
// only), or with `strict` an error instead. So is a mesh whose float coordinates step by more
// than kFloatStepWarning of its diagonal where it lies (float_step_warning; a warning only: the
// commands' own checks decide whether their results can keep their bounds there).
#include <string>

#include "cli/progress.hpp"
#include "core/mesh.hpp"

namespace splatcl::cli {

// Where load_model puts the file's coordinates: as given; about the centre of their bounding box
// where a test holds (splats, whose files record the origin: a warning says so instead of the
// float-step warning); or about a given origin (splats verify: the one its splat file records).
struct ModelOrigin {
  enum Kind { AsGiven, CentreWhen, Given } kind = AsGiven;
  RecentreTest when;     // CentreWhen: splats::recentre_test
  DVec3 given{0, 0, 0};  // Given
};

// `winding`: Orient for the commands whose results face a way (splats, splats verify, ao: an
// inside-out mesh gave splats facing into it and AO near 0), AsGiven where only the surface's place
// matters (csm).
Mesh load_model(const std::string& path, ProgressLine& progress, Winding winding, bool strict = false, const ModelOrigin& origin = {});

// Adds "splatcl: warning: SUBJECT: TEXT" to the warnings printed when the command has succeeded.
void queue_warning(const std::string& subject, const std::string& text);

// Prints the warnings load_model and queue_warning collected (main calls it when a command has
// succeeded).
void print_model_warnings();

}  // namespace splatcl::cli
