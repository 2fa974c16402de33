#pragma once
// A front bumper reading. The contact geometry is tested by the simulator (Vehicle::bumper_contact,
// sim/vehicle.hpp); this is the plain record a sensor stream carries.
namespace starnav {

struct BumperReading {
  double t_s = 0.0;
  bool contact = false;
};

}  // namespace starnav
