#pragma once
// The window loop of `manylights view`: opens a GLFW window (GL 4.5 core),
// a CL runtime sharing with it through the run layer, and a ViewerSession;
// then per frame: input -> script step or camera controls -> session frame
// -> present -> panel -> swap. With a script it ends when the script does;
// otherwise when the window closes (or Esc).
#include <optional>

#include "host/cl/ClRuntime.hpp"
#include "host/view/ViewerScript.hpp"
#include "host/view/ViewerSession.hpp"

namespace ml {

int runViewer(ViewerSetup setup, const DeviceChoice& device, std::optional<ViewerScript> script);

}  // namespace ml
