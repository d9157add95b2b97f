/***************************************************************************
  trajectoryinterpolation.h - a vehicle's pose at any time of its trajectory
  -------------------------------------------------------------------------
  A GNSS/INS trajectory is sampled at its own rate (10-200 Hz); the cameras
  are triggered at other times. The pose at an exposure's time is
  interpolated between the two samples around it:
  - position by a cubic Hermite curve whose tangents are the central
    differences of the neighbouring samples (one-sided at the ends), so a
    10 Hz trajectory through a bend keeps its curvature;
  - attitude by spherical linear interpolation (slerp) of the rotations,
    which has no trouble with a heading through north.
  A time before the first sample, after the last, or between two samples
  further apart than the largest gap allowed is not interpolated (an
  expected outcome, returned, not thrown). Times in seconds.
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_TRAJECTORYINTERPOLATION_H
#define GEOSTATION_GEOMETRY_TRAJECTORYINTERPOLATION_H

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace geostation
{

  struct TrajectoryPose
  {
    double timeS = 0.0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();      //!< metres, any Cartesian frame (a projected CRS)
    Eigen::Matrix3d attitude = Eigen::Matrix3d::Identity();  //!< a rotation (e.g. NED from body)
  };

  struct TrajectoryLookup
  {
    enum class Status
    {
      Interpolated,
      BeforeStart,
      AfterEnd,
      InGap, //!< the samples around the time are further apart than the largest gap allowed
    };
    Status status = Status::Interpolated;
    TrajectoryPose pose;
    double gapS = 0.0; //!< between the samples around the time
  };

  class TrajectoryInterpolator
  {
    public:
      /**
       * `samples` in strictly increasing time. Throws std::invalid_argument
       * with fewer than 2 samples, a time that does not increase (naming the
       * sample, 1-based), a rotation that is not one, or maxGapS <= 0.
       */
      TrajectoryInterpolator( std::vector<TrajectoryPose> samples, double maxGapS );

      TrajectoryLookup at( double timeS ) const;

      double startS() const { return mSamples.front().timeS; }
      double endS() const { return mSamples.back().timeS; }
      //! The median time between samples (s).
      double medianIntervalS() const;

    private:
      Eigen::Vector3d velocity( size_t i ) const;

      std::vector<TrajectoryPose> mSamples;
      std::vector<Eigen::Quaterniond> mRotations;
      double mMaxGapS;
  };

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_TRAJECTORYINTERPOLATION_H
