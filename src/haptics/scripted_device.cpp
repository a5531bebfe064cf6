// Implementation of bemsurg/haptics/scripted_device.hpp and recording_device.hpp: trajectories
// from functions, keyframes and CSV; recording into reserved memory and writing it back as CSV.
#include "bemsurg/haptics/scripted_device.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string_view>

#include "bemsurg/error.hpp"
#include "bemsurg/haptics/recording_device.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg::haptics {

ScriptedDevice::ScriptedDevice(std::function<DeviceState(double)> trajectory, std::string name, double max_force)
    : function_(std::move(trajectory)), name_(std::move(name)), max_force_(max_force) {
  if (!function_) throw InvalidArgumentError("ScriptedDevice: the trajectory function is empty");
}

ScriptedDevice::ScriptedDevice(std::vector<Keyframe> keyframes, std::string name, double max_force)
    : keyframes_(std::move(keyframes)), name_(std::move(name)), max_force_(max_force) {
  if (keyframes_.empty()) throw InvalidArgumentError("ScriptedDevice: no keyframes");
  for (std::size_t i = 0; i < keyframes_.size(); ++i) {
    if (!std::isfinite(keyframes_[i].time) || !keyframes_[i].position.allFinite() || !keyframes_[i].direction.allFinite())
      throw InvalidArgumentError("ScriptedDevice: keyframe " + std::to_string(i) + " is not finite");
    if (i > 0 && keyframes_[i].time < keyframes_[i - 1].time)
      throw InvalidArgumentError("ScriptedDevice: keyframe " + std::to_string(i) + " (t = " + number_text(keyframes_[i].time) +
                                 ") comes before the previous one");
  }
}

DeviceState ScriptedDevice::state_at(double t) const {
  if (function_) return function_(t);
  // The last keyframe at or before t (upper_bound: of equal times, the later one wins: a jump).
  const auto it = std::upper_bound(keyframes_.begin(), keyframes_.end(), t, [](double x, const Keyframe& k) { return x < k.time; });
  DeviceState s;
  if (it == keyframes_.begin()) {
    const Keyframe& k = keyframes_.front();
    s.position = k.position;
    s.direction = k.direction;
    s.orientation = k.orientation;
    s.buttons = k.buttons;
    s.connected = k.connected;
    return s;
  }
  const Keyframe& a = *(it - 1);
  s.buttons = a.buttons;
  s.connected = a.connected;
  if (it == keyframes_.end() || !(it->time > a.time)) {
    s.position = a.position;
    s.direction = a.direction;
    s.orientation = a.orientation;
    return s;
  }
  const Keyframe& b = *it;
  const double w = (t - a.time) / (b.time - a.time);
  s.position = (1.0 - w) * a.position + w * b.position;
  const Eigen::Vector3d d = (1.0 - w) * a.direction + w * b.direction;
  const double n = d.norm();
  s.direction = n > 0.0 ? Eigen::Vector3d(d / n) : a.direction;
  s.orientation = a.orientation.slerp(w, b.orientation);
  return s;
}

DeviceState ScriptedDevice::read(double session_time) { return state_at(session_time); }

std::vector<Keyframe> ScriptedDevice::read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open the trajectory CSV");
  std::string line;
  if (!std::getline(in, line)) throw IoError(path + ": empty file (expected a header time,x,y,z,...)");
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    std::string h;
    while (std::getline(ss, h, ',')) {
      h.erase(std::remove_if(h.begin(), h.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); }), h.end());
      header.push_back(h);
    }
  }
  auto column = [&](const char* name) -> int {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int ct = column("time"), cx = column("x"), cy = column("y"), cz = column("z");
  if (ct < 0 || cx < 0 || cy < 0 || cz < 0)
    throw IoError(path + " line 1: the header must name the columns time, x, y, z (optional dx, dy, dz, buttons, connected)");
  const int cdx = column("dx"), cdy = column("dy"), cdz = column("dz"), cb = column("buttons"), cc = column("connected");
  std::vector<Keyframe> out;
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      const auto first = cell.find_first_not_of(" \t\r"), last = cell.find_last_not_of(" \t\r");
      const std::optional<double> x =
          first == std::string::npos ? std::nullopt : parse_number<double>(std::string_view(cell).substr(first, last - first + 1));
      if (!x)
        throw IoError(path + " line " + std::to_string(line_no) + ": column " + std::to_string(v.size() + 1) + " is not a number: '" +
                      cell + "'");
      v.push_back(*x);
      if (!std::isfinite(v.back()))
        throw IoError(path + " line " + std::to_string(line_no) + ": column " + std::to_string(v.size()) + " is not finite");
    }
    if (v.size() < header.size())
      throw IoError(path + " line " + std::to_string(line_no) + ": " + std::to_string(v.size()) + " values, the header has " +
                    std::to_string(header.size()));
    Keyframe k;
    k.time = v[static_cast<std::size_t>(ct)];
    k.position = {v[static_cast<std::size_t>(cx)], v[static_cast<std::size_t>(cy)], v[static_cast<std::size_t>(cz)]};
    if (cdx >= 0 && cdy >= 0 && cdz >= 0) {
      const Eigen::Vector3d d(v[static_cast<std::size_t>(cdx)], v[static_cast<std::size_t>(cdy)], v[static_cast<std::size_t>(cdz)]);
      if (!(d.norm() > 0.0)) throw IoError(path + " line " + std::to_string(line_no) + ": the direction dx, dy, dz is zero");
      k.direction = d.normalized();
    }
    if (cb >= 0) {
      const double b = v[static_cast<std::size_t>(cb)];
      if (b < 0 || b != std::floor(b) || b > 4294967295.0)
        throw IoError(path + " line " + std::to_string(line_no) + ": buttons must be a non-negative integer bit mask");
      k.buttons = static_cast<std::uint32_t>(b);
    }
    if (cc >= 0) k.connected = v[static_cast<std::size_t>(cc)] != 0.0;
    if (!out.empty() && k.time < out.back().time)
      throw IoError(path + " line " + std::to_string(line_no) + ": time " + number_text(k.time) + " goes back (times must not decrease)");
    out.push_back(k);
  }
  if (out.empty()) throw IoError(path + ": no samples after the header");
  return out;
}

// ---- RecordingDevice ---------------------------------------------------------------------------

RecordingDevice::RecordingDevice(std::unique_ptr<HapticDevice> inner, std::size_t capacity)
    : inner_(std::move(inner)), capacity_(capacity) {
  if (!inner_) throw InvalidArgumentError("RecordingDevice: no device to record");
  samples_.reserve(capacity);
}

DeviceState RecordingDevice::read(double session_time) {
  const DeviceState s = inner_->read(session_time);
  if (samples_.size() < capacity_) {
    Sample r;
    r.time = session_time;
    r.state = s;
    samples_.push_back(r);  // within the reserved capacity: no allocation
  } else {
    ++overflow_;
  }
  return s;
}

void RecordingDevice::write_force(const Eigen::Vector3d& force) {
  if (!samples_.empty() && overflow_ == 0) samples_.back().force = force;
  inner_->write_force(force);
}

void RecordingDevice::write_csv(const std::string& path) const {
  std::ofstream out(path);
  if (!out) throw IoError("cannot write the recording " + path);
  use_classic_locale(out);  // a file ScriptedDevice::read_csv reads back, whatever the application's locale
  out << "time,x,y,z,dx,dy,dz,buttons,connected,fx,fy,fz\n" << std::setprecision(17);
  for (const Sample& s : samples_) {
    const DeviceState& d = s.state;
    out << s.time << ',' << d.position.x() << ',' << d.position.y() << ',' << d.position.z() << ',' << d.direction.x() << ','
        << d.direction.y() << ',' << d.direction.z() << ',' << d.buttons << ',' << (d.connected ? 1 : 0) << ',' << s.force.x() << ','
        << s.force.y() << ',' << s.force.z() << '\n';
  }
  if (!out) throw IoError("writing the recording " + path + " failed");
}

}  // namespace bemsurg::haptics
