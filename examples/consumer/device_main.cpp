// A device program as bemsurg's users write one: it links bemsurg::haptics only (the adapter and
// the compiled numerical core, no JSON and no Gmsh; CI checks the linked libraries). It plays a
// scripted device through the force limiter and checks that the force it would send stays finite
// and within the device's limit, ramping at the limiter's rate.
#include <bemsurg/haptics/force_limiter.hpp>
#include <bemsurg/haptics/scripted_device.hpp>
#include <cmath>
#include <iostream>
#include <vector>

int main() {
  using namespace bemsurg::haptics;
  std::vector<Keyframe> keys(2);
  keys[1].time = 1.0;
  keys[1].position = Eigen::Vector3d(0.0, 0.0, -0.01);
  ScriptedDevice device(keys, "consumer device", 3.3);
  ForceLimiter limiter(device.max_force(), 50.0);  // 3.3 N at most, 50 N/s at most
  const double dt = 1e-3;
  Eigen::Vector3d sent = Eigen::Vector3d::Zero();
  for (int tick = 0; tick < 1000; ++tick) {
    const DeviceState state = device.read(tick * dt);
    const Eigen::Vector3d wanted = -1000.0 * state.position;  // a stiff spring: up to 10 N asked
    const Eigen::Vector3d force = limiter(wanted, dt);
    if (!force.allFinite() || force.norm() > device.max_force() * (1 + 1e-12) || (force - sent).norm() > 50.0 * dt * (1 + 1e-9)) {
      std::cerr << "consumer_device: tick " << tick << ": force " << force.transpose() << " breaks the limits\n";
      return 1;
    }
    device.write_force(force);
    sent = force;
  }
  std::cout << "consumer_device: 1000 ticks, final force " << sent.norm() << " N (limit " << device.max_force() << " N)\n";
  return sent.norm() > 0.0 ? 0 : 1;
}
