#pragma once
// Internal to the waypoint mission (WaypointMission.cpp, WaypointBypass.cpp): the constants of
// its BYPASS phase, the edge following round an obstacle in the way of a target.

namespace carril::fw::waypoint_bypass {

// DRIVE's phase while going round (compared by address: one array, one address in every file).
inline constexpr char kBypass[] = "bypass";

// BYPASS: begins with a cell in the corridor to the target within its keeping distance plus
// kEnterMarginM; ends when that corridor, kLeaveWidenM wider, is clear for kClearAheadM, or when
// the edge followed is farther than the keeping distance plus kLostM.
inline constexpr double kEnterMarginM = 0.1;  // [m]
inline constexpr double kClearAheadM = 0.8;   // [m]
inline constexpr double kLeaveWidenM = 0.05;  // [m]
inline constexpr double kLostM = 0.35;        // [m]
inline constexpr double kTrackM = 0.2;        // the edge followed moves at most this far a tick [m]
// The side: the mean offset across the line of the corridor's cells within kSideDepthM past the
// first; within kSideTieM of the line, VFF's push decides.
inline constexpr double kSideDepthM = 0.3;  // [m]
inline constexpr double kSideTieM = 0.05;   // [m]
inline constexpr double kKeepGain =
    4.0;  // heading correction per metre off the keeping distance [1/m]
inline constexpr double kCircledM = 0.2;  // back this close to where the bypass began: circled [m]
inline constexpr double kAwayM = 0.5;     // after having been this far from it [m]

}  // namespace carril::fw::waypoint_bypass
