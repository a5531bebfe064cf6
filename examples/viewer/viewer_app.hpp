// examples/viewer/viewer_app.hpp: the viewer program: interactive (mouse as a haptic device, haptic
// loop on its own thread) or headless (an action script played frame by frame, PNGs written).
// docs/viewer.md describes the controls and the displays.
#pragma once

#include <string>
#include <vector>

namespace bemsurg::viewer {

struct ViewerOptions {
  std::string scene;       // --scene FILE ("" = default model)
  std::string script;      // --script ACTIONS.json (headless)
  int frames = 0;          // --frames N (headless)
  std::string screenshot;  // --screenshot OUT.png (headless: the last frame)
  std::vector<int> shots;  // --shots F1,F2,...: also write OUT-fNNNN.png at these frames
  double fps = 30.0;       // --fps: script seconds per frame = 1/fps (headless)
  int width = 1280, height = 800;
  bool headless = false;    // any of --script/--frames/--screenshot given
  std::string record;       // --record FILE: write the mouse session as an action script (interactive)
  double quit_after = 0.0;  // --quit-after S: close the window after S seconds and print the rates (interactive)
};

/// Runs the viewer; returns the process exit code. Errors in headless mode are printed and give
/// a non-zero code; in the window they are shown and the program goes on.
int run_viewer(const ViewerOptions& options);

}  // namespace bemsurg::viewer
