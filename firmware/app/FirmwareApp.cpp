#include "firmware/app/FirmwareApp.hpp"

namespace carril::fw {

const ActuatorCommand& FirmwareApp::step() {
  frame_.now_ns = dev_.clock.now_ns();
  frame_.camera = dev_.camera.latest();
  frame_.scan = dev_.scanner.latest();
  frame_.cloud = dev_.cloud != nullptr ? dev_.cloud->latest() : nullptr;
  frame_.imu = dev_.imu.read();
  dev_.drives.read(frame_.wheels);

  cmd_ = ctl_.tick(frame_);

  // Requests are sent on change (a drive's state machine takes them as edges); setpoints every
  // period, zero unless running.
  if (cmd_.drive != applied_) {
    switch (cmd_.drive) {
      case DriveRequest::Run:
        dev_.drives.enable();
        break;
      case DriveRequest::QuickStop:
        dev_.drives.quick_stop();
        break;
      case DriveRequest::Disable:
        dev_.drives.disable();
        break;
    }
    applied_ = cmd_.drive;
  }
  float zero[hal::kMaxWheels] = {};
  const float* sp = cmd_.drive == DriveRequest::Run ? cmd_.wheel_radps.data() : zero;
  dev_.drives.set_velocity(sp, dev_.drives.count());
  // Once per period, after every command of the period: a bus backend sends PDOs and SYNC here.
  dev_.drives.sync();
  return cmd_;
}

}  // namespace carril::fw
