/***************************************************************************
  trajectoryimport.h - a mapping van's calibration plus trajectory as a block
  -------------------------------------------------------------------------
  The trajectory is a CSV table, one row per exposure station; or, with an
  events table (time; station; image or image_<camera id>), a high-rate
  GNSS/INS solution sampled at its own times, in which each event's pose is
  interpolated (geometry/trajectoryinterpolation.h: cubic Hermite
  positions, slerp attitudes; events outside the trajectory or in a gap
  longer than maxTrajectoryGapS are left out and reported). Columns are
  matched by name, case-insensitively:
    time        time, timestamp, gps_time, utc (optional, kept as text)
    station     station, station_id, id (optional; default S0001, S0002, ...)
    position    X, Y, Z (or easting, northing, height) in the block CRS, or
                latitude, longitude, height (lat/lon, h, alt, ellipsoidal_height)
                in WGS 84, heights passed through as they are
    attitude    roll, pitch, heading (yaw): the body's attitude, x forward,
                y right, z down, heading from true north, clockwise;
                or omega, phi, kappa: the camera's own exterior orientation
                (docs/conventions.md §3), one camera, no lever arm or boresight
    images      image (one camera) or image_<camera id>; otherwise each
                camera's image_pattern
  Angles are in degrees unless the options say radians; radians given as
  degrees (every value within +-2 pi, roll and pitch within +-0.2, heading
  spanning more than 0.5 over at least ten rows) are refused.

  Each camera's pose: worldFromBody = gridFromEnu * enuFromNed *
  Rz(heading) Ry(pitch) Rx(roll); the centre is the row's position plus
  worldFromBody * lever arm; worldFromCamera = worldFromBody *
  Rz(bh) Ry(bp) Rx(br) * bodyFromForwardCamera, where the forward camera
  looks along body x with image right = body y and image up = body -z.
  gridFromEnu turns true north into the projected CRS's grid north
  (meridian convergence), computed with PROJ at every row.
 ***************************************************************************/
#ifndef GEOSTATION_IO_TRAJECTORYIMPORT_H
#define GEOSTATION_IO_TRAJECTORYIMPORT_H

#include <filesystem>
#include <string>
#include <vector>

#include "io/blockimport.h"
#include "io/opencvcalibration.h"

namespace geostation
{

  struct TrajectoryImportOptions
  {
    std::string crs;                     //!< the block CRS (projected, metres); required
    bool anglesInRadians = false;        //!< the table's angles are radians
    std::filesystem::path imageFolder;   //!< image names resolve here; empty: the trajectory file's folder
    bool requireImageFiles = true;       //!< every image must exist, decode and have its camera's size
    //! Exposure events (time, and image names or the rig's patterns): each becomes a station whose pose is
    //! interpolated in the trajectory (a high-rate GNSS/INS solution) at its time; empty: one station per row.
    std::filesystem::path eventsCsv;
    double maxTrajectoryGapS = 1.0;      //!< events between trajectory samples further apart are left out
  };

  /**
   * Builds a block from a rig's cameras and a trajectory table. Throws
   * std::invalid_argument with one sentence (unknown columns, a row that
   * is not a number, angles that look like radians, an image missing, ...);
   * nothing is written.
   */
  BlockImportSummary importTrajectory( const std::vector<RigCamera> &rig, const std::filesystem::path &trajectoryCsv, const TrajectoryImportOptions &options );

  /**
   * worldFromCamera of a rig camera on a body with the given attitude
   * (roll, pitch, heading in degrees) in the grid whose north makes
   * `convergenceDeg` with true north (grid azimuth = true azimuth -
   * convergenceDeg).
   */
  Eigen::Matrix3d worldFromRigCamera( const Eigen::Vector3d &rollPitchHeadingDeg, const RigCamera &camera, double convergenceDeg );

  //! worldFromBody for a body attitude (roll, pitch, heading in degrees) and meridian convergence.
  Eigen::Matrix3d worldFromBody( const Eigen::Vector3d &rollPitchHeadingDeg, double convergenceDeg );

} // namespace geostation

#endif // GEOSTATION_IO_TRAJECTORYIMPORT_H
