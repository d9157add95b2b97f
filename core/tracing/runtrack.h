/***************************************************************************
  runtrack.h - the run a line is traced through: its stations, the image
  that plays the seed image's part at each, their track and the road under it
  -------------------------------------------------------------------------
  Internal to tracing (RoadTraceRun keeps one). The stations in run order
  (io/stationsequence.h); at each, the oriented image that plays the seed
  image's part in the rig (rigroles.h: by geometry, not by camera entry);
  the track of those cameras' projection centres, a station out of order
  left out (it would fold the track back on itself), and the track with
  its heights smoothed over 30 m; the road surface under a point, hung
  from a camera by the van's camera height, and the road plane of a
  station with its heights from that surface. Plan distances in metres,
  heights in the block CRS.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_RUNTRACK_H
#define GEOSTATION_TRACING_RUNTRACK_H

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "io/block.h"
#include "io/stationsequence.h"
#include "geometry/windowshape.h"

namespace geostation
{

  class RunTrack
  {
    public:
      /**
       * The run of `seedImage`'s block, the seed's camera `cameraHeightM`
       * above the road. Throws std::invalid_argument for a seed image that
       * is not oriented or belongs to no station.
       */
      RunTrack( const Block &block, const BlockImage &seedImage, double cameraHeightM );

      const StationSequence &sequence() const { return mSequence; }
      //! The seed image's station, an index into sequence().
      int seedStation() const { return mSeedStation; }
      //! The oriented image that plays the seed image's part at a station; nullptr if none (or out of range).
      const BlockImage *referenceImageAt( int stationIndex ) const;
      //! The reference cameras' path through the run, in run order.
      const std::vector<Eigen::Vector3d> &trajectory() const { return mTrajectory; }

      //! The road surface under a point, hung from a camera at `cameraZ` over `cameraXY`: the smoothed track's shape, the camera's height below it there.
      std::optional<double> surfaceHeight( const Eigen::Vector2d &xy, double cameraZ, const Eigen::Vector2d &cameraXY ) const;
      //! The road surface seen from a station: the plane under it, its height then taken from the track where the ray meets it (refers to this track).
      GroundOfPixel roadPlaneOf( double cameraZ, const Eigen::Vector2d &cameraXY ) const;

    private:
      static int seedStationIndex( const StationSequence &sequence, const BlockImage &seedImage );
      std::vector<Eigen::Vector3d> referenceTrajectory() const;

      const StationSequence mSequence;
      const int mSeedStation;
      const std::vector<const BlockImage *> mReferenceImages;
      const std::vector<Eigen::Vector3d> mTrajectory, mSmoothTrack;
      const double mCameraHeightM;
  };

} // namespace geostation

#endif // GEOSTATION_TRACING_RUNTRACK_H
