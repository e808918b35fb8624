#pragma once
// Glue between the HAL and the Controller: reads every device into a SensorFrame, runs one tick,
// and writes the ActuatorCommand back to the drives. The same code runs on every target.
#include "firmware/app/Controller.hpp"
#include "hal/Devices.hpp"

namespace carril::fw {

class FirmwareApp {
 public:
  FirmwareApp(const hal::Devices& dev, Controller& ctl) : dev_(dev), ctl_(ctl) {}
  // One control period: sense, tick, actuate.
  const ActuatorCommand& step();
  const SensorFrame& last_frame() const { return frame_; }
  const ActuatorCommand& last_command() const { return cmd_; }

 private:
  hal::Devices dev_;
  Controller& ctl_;
  SensorFrame frame_;
  ActuatorCommand cmd_;
  DriveRequest applied_ = DriveRequest::Disable;
};

}  // namespace carril::fw
