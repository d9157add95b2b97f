/***************************************************************************
  roadtracerun.h - the state and steps of one road line traced through a run
  -------------------------------------------------------------------------
  Internal to tracing: traceRoadLine() (roadtracer.h) is the interface.
  RoadTraceRun walks the run station by station; each station is traced in
  named steps: open its images (openStation), follow the line in the
  reference image (followInReference), find it in the partner and
  intersect (matchInPartner), append the station's vertices to the run's
  line (appendToRun), and hand the line over to the next station
  (linkToNext, by stationhandover.h). finish() scales the sigmas by the
  run's sigma0. The run itself - its stations, the image playing the
  seed's part at each, their track and the road under it - is a RunTrack
  (runtrack.h).
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_ROADTRACERUN_H
#define GEOSTATION_TRACING_ROADTRACERUN_H

#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tracing/rigroles.h"
#include "tracing/roadtracer.h"
#include "tracing/runline.h"
#include "tracing/runtrack.h"
#include "tracing/stationstereo.h"
#include "io/stationsequence.h"

namespace geostation
{
  //! A station traced before, kept so that the next stations' vertices can be observed in its images.
  struct StationBehind
  {
    std::string stationId;
    std::vector<std::string> imageIds;
    std::vector<OrientedImage> images;
    std::vector<std::shared_ptr<const cv::Mat>> greys;

    StationView view() const
    {
      StationView v { stationId, {} };
      for ( size_t i = 0; i < images.size(); ++i )
        v.images.push_back( { imageIds[i], &images[i], greys[i].get() } );
      return v;
    }
  };

  /**
   * A station's images and what the steps of its tracing share. Built in
   * place and never copied: its functions (ground, follow, request) refer
   * to its members.
   */
  struct StationAt
  {
    const SequenceStation *station = nullptr;
    const BlockImage *referenceImage = nullptr, *partnerImage = nullptr;
    std::optional<OrientedImage> reference, partner;
    std::shared_ptr<const cv::Mat> partnerGrey;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(); //!< the reference camera's projection centre
    GroundOfPixel ground;                             //!< the road surface (or the options' ground) under a pixel of either image
    double rangeLimitM = 0.0;                         //!< the distance limit: ground distance from centre
    std::optional<Eigen::Vector3d> startGround;       //!< the start on the ground
    LineFollowOptions follow;                         //!< with the ground distance in the reference image
    FollowRequest request;                            //!< the reference image's

    StationAt() = default;
    StationAt( const StationAt & ) = delete;
    StationAt &operator=( const StationAt & ) = delete;

    //! True for a pixel of `image` (reference or partner) whose ground is within `limitM` of the reference camera.
    std::function<bool( const Eigen::Vector2d & )> withinLimitOf( const OrientedImage &image, double limitM ) const
    {
      return [&image, this, limitM]( const Eigen::Vector2d &pixel )
      {
        const std::optional<Eigen::Vector3d> g = ground( image, pixel );
        return g && ( *g - centre ).head<2>().norm() <= limitM;
      };
    }
  };

  //! A station's line in its reference image and the method that followed it.
  struct ReferenceLine
  {
    LineFollowResult followed;
    TraceMethod method = TraceMethod::Polynomial;
  };

  //! Traces one line through the run (roadtracer.h): the run's state and its steps. Lives for one traceRoadLine() call.
  class RoadTraceRun
  {
    public:
      RoadTraceRun( const Block &block, const TraceSeed &seed, const RoadTraceOptions &options, const GreyImageSource &images );
      RoadTraceSummary run();

      static double horizontalDistance( const Eigen::Vector3d &a, const Eigen::Vector3d &b ) { return ( a - b ).head<2>().norm(); }

    private:
      static const RoadTraceOptions &checked( const RoadTraceOptions &options );
      bool startAtSeed();
      bool openStation( StationAt &at );
      bool choosePartner( const StationAt &at );
      double rangeLimitAt( const Eigen::Vector3d &centre ) const;
      void prepareFollowing( StationAt &at );
      LineFollowResult keepInCourse( const StationAt &at, LineFollowResult result ) const;
      ReferenceLine followInReference( const StationAt &at ) const;
      StationStereo matchInPartner( const StationAt &at, const ReferenceLine &line, TracedStation &record );
      StationPartSummary appendToRun( const StationAt &at, const std::vector<LineVertex3d> &vertices );
      std::vector<Eigen::Vector3d> lineOnGround( const StationAt &at, const FollowResult &followed ) const;
      void updateLineDirection( const std::vector<Eigen::Vector3d> &groundLine );
      bool mayGoOn( const StationAt &at, int stationsDone, const std::vector<Eigen::Vector3d> &groundLine, const StartMatch &partnerStart );
      bool linkToNext( const StationAt &at, const FollowResult &followed, const std::vector<Eigen::Vector3d> &groundLine, size_t firstOfStation );
      void finish();
      void stopWith( TraceStop stop, const std::string &message );

      const Block &mBlock;
      const TraceSeed &mSeed;
      const RoadTraceOptions &mOptions;
      const GreyImageSource &mImages;
      const BlockImage &mSeedImage;
      const RunTrack mTrack;                       //!< the stations, the seed image's part at each, their track and the road under it
      const StationSequence &mSequence;            //!< mTrack's

      RoadTraceSummary mOut;
      int mK;                                      //!< the station being traced, in the sequence
      std::shared_ptr<const cv::Mat> mReferenceGrey;
      std::string mPartnerSeedId, mPartnerCameraId; //!< the partner chosen at the seed station, and its camera
      RigRelation mPartnerRelation;                //!< where it lies beside the reference; the same at every station
      Eigen::Vector2d mStart = Eigen::Vector2d::Zero(), mDirection = Eigen::Vector2d::Zero(); //!< in the station's reference image
      LineProfile mProfile;
      double mWidthTimesRange = 0.0;               //!< stripes narrow as 1 / range
      size_t mKeep = 0;                            //!< run vertices kept when the next station's are appended
      int mStep = 0;                               //!< +1 or -1 through the run, set at the first handover
      Eigen::Vector3d mLineDirection = Eigen::Vector3d::Zero(); //!< on the ground, over the line's last 20 m
      std::optional<Eigen::Vector3d> mPreviousCentre; //!< the last station's reference camera
      int mConsecutiveLost = 0;
      std::deque<StationBehind> mBehind;           //!< the stations traced before, nearest first
  };

} // namespace geostation

#endif // GEOSTATION_TRACING_ROADTRACERUN_H
