// bemsurg-viewer: prod, pinch, retract and cut a deformable body with the mouse and see the forces
// live; or, headless, play an action script and write PNG screenshots (docs/viewer.md).
//
//   bemsurg-viewer [--scene FILE] [--record FILE]
//   bemsurg-viewer [--scene FILE] --script ACTIONS.json --frames N --screenshot OUT.png
//                  [--shots F1,F2,...] [--fps F] [--size WxH]
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "bemsurg/memory_budget.hpp"
#include "options/option_parser.hpp"
#include "viewer_app.hpp"

namespace {

constexpr const char* kUsage =
    "usage: bemsurg-viewer [--scene FILE] [--record FILE] [--quit-after SECONDS]\n"
    "       bemsurg-viewer [--scene FILE] --script ACTIONS.json --frames N --screenshot OUT.png\n"
    "                      [--shots F1,F2,...] [--fps F] [--size WxH]\n"
    "\n"
    "Without --script: opens a window on the scene (default: the built-in model) and lets you\n"
    "prod, pinch, retract and cut it with the mouse (docs/viewer.md).\n"
    "With --script (headless): plays the action script for N frames (frame f shows the script at\n"
    "f/F seconds) and writes the last frame to OUT.png; --shots also writes OUT-fNNNN.png at the\n"
    "frames listed (0-based). Needs a display: on a machine without one run\n"
    "  xvfb-run -a -s \"-screen 0 1280x800x24\" bemsurg-viewer --script ... \n"
    "Exit status: 0 success, 1 bad input (scene, script, screenshot path), 2 usage, 3 no display.\n";

/// "WxH" as a window size of at least 320 x 240 and at most 8192 x 8192.
void read_size(const std::string& text, bemsurg::viewer::ViewerOptions& o) {
  const std::size_t x = text.find('x');
  const std::optional<int> w = bemsurg::parse_number<int>(std::string_view(text).substr(0, x));
  const std::optional<int> h = x == std::string::npos ? std::nullopt : bemsurg::parse_number<int>(std::string_view(text).substr(x + 1));
  if (!w || !h || *w < 320 || *w > 8192 || *h < 240 || *h > 8192)
    throw std::invalid_argument("WxH, W from 320 to 8192 and H from 240 to 8192");
  o.width = *w;
  o.height = *h;
}

}  // namespace

int main(int argc, char** argv) {
  bemsurg::viewer::ViewerOptions o;
  bemsurg::cli::OptionParser parser("bemsurg-viewer", kUsage);
  parser.value("--scene", "FILE", o.scene, "the scene (docs/scene-format.md)").default_text("the built-in model");
  parser.value("--record", "FILE", o.record, "write the mouse session to FILE as an action script");
  parser.value("--quit-after", "SECONDS", o.quit_after, "close the window after SECONDS and print the rates")
      .above(0.0)
      .default_text("never");
  parser.value("--script", "ACTIONS.json", o.script, "play the action script headless (docs/actions.md)");
  parser.value("--frames", "N", o.frames, "frames to play (headless: required)").between(1, 1000000).default_text("");
  parser.value("--screenshot", "OUT.png", o.screenshot, "where the last frame goes (headless)");
  parser.value("--shots", "F1,F2,...", o.shots, "frames also written to OUT-fNNNN.png (headless)").between(0, 1000000);
  parser.value("--fps", "F", o.fps, "frames per script second (headless)").above(0.0);
  parser.custom_value("--size", "WxH", "the picture's size (headless)", [&o](const std::string& text) { read_size(text, o); })
      .default_text(std::to_string(o.width) + "x" + std::to_string(o.height));
  const auto check = [&] {
    // Any of the headless options asks for headless mode, which needs all three.
    o.headless = parser.given("--script") || parser.given("--frames") || parser.given("--screenshot");
    if (!o.headless) return;
    if (o.script.empty())
      throw bemsurg::cli::UsageError("bemsurg-viewer: headless mode (--frames/--screenshot) needs --script ACTIONS.json");
    if (!parser.given("--frames")) throw bemsurg::cli::UsageError("bemsurg-viewer: headless mode needs --frames N");
    if (o.screenshot.empty()) throw bemsurg::cli::UsageError("bemsurg-viewer: headless mode needs --screenshot OUT.png");
  };
  if (const std::optional<int> status = bemsurg::cli::parse_command_line(parser, argc, argv, check)) return *status;
  // The viewer cuts: its steps' large temporaries (the accumulated rank's matrices, the changed rows
  // and columns) then reuse freed memory instead of touching fresh pages every step, as `bemsurg cut`
  // and `bemsurg session` do (bemsurg/memory_budget.hpp).
  bemsurg::reuse_freed_memory();
  try {
    return bemsurg::viewer::run_viewer(o);
  } catch (const std::exception& e) {
    std::cerr << "bemsurg-viewer: " << e.what() << "\n";
    return 1;
  }
}
