#pragma once
// The data bus of the line-following firmware: one topic per message, in the order data flows.
// Each has exactly one producer; consumers read it through their own Reader (firmware/core/Topic).
//
//   topic       message          producer         consumers
//   frame       SensorFrame      Controller       SensorWatch, WheelOdometry, LinePerception,
//                                                 ObstacleSensing, MissionRunner, MotionOutput
//   odometry    OdometryMsg      WheelOdometry    SensorWatch, LinePerception, ObstacleSensing,
//                                                 FollowLineMission, MissionRunner (guard),
//                                                 Localisation
//   pose        OdometryMsg      Localisation     Mapping, GotoMission (map frame; = odometry
//                                                 without a map)
//   line        LineObservation  LinePerception   FollowLineMission
//   obstacles   ObstacleField    ObstacleSensing  FollowLineMission, MissionRunner (guard)
//   motion      MotionRequest    MissionRunner    MotionOutput
//   command     ActuatorCommand  MotionOutput     Controller (to the drives)
#include "firmware/control/MotionRequest.hpp"
#include "firmware/core/Frames.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/estimation/WheelOdometry.hpp"
#include "firmware/perception/LinePerception.hpp"
#include "firmware/perception/ObstacleField.hpp"

namespace carril::fw {

struct LineBus {
  // `remember_obstacles_m`: how far beyond the body's circumscribed circle the obstacle field
  // keeps what leaves the lidar's view (for the turn in place of a lost robot; 0: not at all) [m].
  LineBus(const Footprint& fp, double lidar_x, double lidar_y, double lidar_yaw,
          double remember_obstacles_m)
      : obstacles(fp, lidar_x, lidar_y, lidar_yaw, remember_obstacles_m) {}

  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odometry;
  Topic<OdometryMsg> pose;
  Topic<LineObservation> line;
  Topic<ObstacleField> obstacles;
  Topic<MotionRequest> motion;
  Topic<ActuatorCommand> command;
};

}  // namespace carril::fw
