// bemsurg-viewer: prod, pinch, retract and cut a deformable body with the mouse and see the forces
// live; or, headless, play an action script and write PNG screenshots (docs/viewer.md).
//
//   bemsurg-viewer [--scene FILE] [--record FILE]
//   bemsurg-viewer [--scene FILE] --script ACTIONS.json --frames N --screenshot OUT.png
//                  [--shots F1,F2,...] [--fps F] [--size WxH]
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>

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
    "f/F seconds, F = 30 by default) and writes the last frame to OUT.png; --shots also writes\n"
    "OUT-fNNNN.png at the frames listed (0-based). Needs a display: on a machine without one run\n"
    "  xvfb-run -a -s \"-screen 0 1280x800x24\" bemsurg-viewer --script ... \n"
    "Exit status: 0 success, 1 bad input (scene, script, screenshot path), 2 usage, 3 no display.\n";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

int parse_int(const std::string& opt, const std::string& text, int lo, int hi) {
  try {
    std::size_t used = 0;
    const long v = std::stol(text, &used);
    if (used == text.size() && v >= lo && v <= hi) return static_cast<int>(v);
  } catch (const std::exception&) {
  }
  throw UsageError(opt + " expects an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got '" +
                   text + "'");
}

}  // namespace

int main(int argc, char** argv) {
  bemsurg::viewer::ViewerOptions o;
  try {
    bool frames_given = false;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw UsageError(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "-h" || arg == "--help") {
        std::cout << kUsage;
        return 0;
      } else if (arg == "--scene") {
        o.scene = value();
      } else if (arg == "--script") {
        o.script = value();
        o.headless = true;
      } else if (arg == "--frames") {
        o.frames = parse_int(arg, value(), 1, 1000000);
        frames_given = true;
        o.headless = true;
      } else if (arg == "--screenshot") {
        o.screenshot = value();
        o.headless = true;
      } else if (arg == "--shots") {
        std::stringstream ss(value());
        std::string item;
        while (std::getline(ss, item, ',')) o.shots.push_back(parse_int(arg, item, 0, 1000000));
      } else if (arg == "--fps") {
        const std::string v = value();
        std::size_t used = 0;
        double f = 0.0;
        try {
          f = std::stod(v, &used);
        } catch (const std::exception&) {
        }
        if (used != v.size() || !(f > 0.0) || !std::isfinite(f)) throw UsageError("--fps expects a positive number, got '" + v + "'");
        o.fps = f;
      } else if (arg == "--size") {
        const std::string v = value();
        const auto x = v.find('x');
        if (x == std::string::npos) throw UsageError("--size expects WxH, got '" + v + "'");
        o.width = parse_int("--size", v.substr(0, x), 320, 8192);
        o.height = parse_int("--size", v.substr(x + 1), 240, 8192);
      } else if (arg == "--quit-after") {
        const std::string v = value();
        std::size_t used = 0;
        double q = 0.0;
        try {
          q = std::stod(v, &used);
        } catch (const std::exception&) {
        }
        if (used != v.size() || !(q > 0.0) || !std::isfinite(q)) throw UsageError("--quit-after expects positive seconds, got '" + v + "'");
        o.quit_after = q;
      } else if (arg == "--record") {
        o.record = value();
      } else {
        throw UsageError("unknown argument '" + arg + "'");
      }
    }
    if (o.headless) {
      if (o.script.empty()) throw UsageError("headless mode (--frames/--screenshot) needs --script ACTIONS.json");
      if (!frames_given) throw UsageError("headless mode needs --frames N");
      if (o.screenshot.empty()) throw UsageError("headless mode needs --screenshot OUT.png");
    }
  } catch (const UsageError& e) {
    std::cerr << "bemsurg-viewer: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    return bemsurg::viewer::run_viewer(o);
  } catch (const std::exception& e) {
    std::cerr << "bemsurg-viewer: " << e.what() << "\n";
    return 1;
  }
}
