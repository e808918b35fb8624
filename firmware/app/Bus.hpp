#pragma once
// The firmware's data bus: one topic per message (firmware/msg/), in the order data flows. Each
// has exactly one producer; consumers read it through their own Reader (firmware/core/Topic).
//
//   topic       message          producer         consumers
//   frame       SensorFrame      Controller       SensorWatch, WheelOdometry, Localisation,
//                                                 LinePerception, ObstacleSensing, Mapping,
//                                                 MissionRunner, MotionOutput
//   odometry    OdometryMsg      WheelOdometry    SensorWatch, LinePerception, ObstacleSensing,
//                                                 FollowLineMission, MissionRunner (guard),
//                                                 Localisation
//   pose        OdometryMsg      Localisation     Mapping, GotoMission, WaypointMission,
//                                                 CoverageMission (map frame; = odometry
//                                                 without a map)
//   line        LineObservation  LinePerception   FollowLineMission
//   obstacles   ObstacleField    ObstacleSensing  FollowLineMission, MissionRunner (guard)
//   costmap     CostmapMsg       Mapping          FollowLineMission, GotoMission, WaypointMission,
//                                                 CoverageMission, MissionRunner (motion check)
//   motion      MotionRequest    MissionRunner    MotionOutput
//   command     ActuatorCommand  MotionOutput     Controller (to the drives)
#include "firmware/core/Topic.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/CostmapView.hpp"
#include "firmware/msg/LineObservation.hpp"
#include "firmware/msg/MotionRequest.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/msg/SensorFrame.hpp"

namespace carril::fw {

struct Bus {
  // `remember_obstacles_m`: how far beyond the body's circumscribed circle the obstacle field
  // keeps what leaves the lidar's view (for the turn in place of a lost robot; 0: not at all) [m].
  Bus(const Footprint& fp, double lidar_x, double lidar_y, double lidar_yaw,
      double remember_obstacles_m)
      : obstacles(fp, lidar_x, lidar_y, lidar_yaw, remember_obstacles_m) {}

  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odometry;
  Topic<OdometryMsg> pose;
  Topic<LineObservation> line;
  Topic<ObstacleField> obstacles;
  Topic<CostmapMsg> costmap;
  Topic<MotionRequest> motion;
  Topic<ActuatorCommand> command;
};

}  // namespace carril::fw
