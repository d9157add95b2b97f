/***************************************************************************
  roadtracerun.cpp - a road line traced through a run: set-up, the loop
  over the stations, a station's images, and the finish (roadtracerun.h)
 ***************************************************************************/
#include "tracing/roadtracerun.h"
#include "tracing/trackgeometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

namespace geostation
{
  namespace
  {
    //! The station's other oriented image that sees the ground point, its optical axis closest to the reference's.
    const BlockImage *partnerSeeing( const Block &block, const SequenceStation &station, const BlockImage &reference, const OrientedImage &referenceImage,
                                     const Eigen::Vector3d &ground )
    {
      const BlockImage *best = nullptr;
      double bestCos = -2.0;
      const Eigen::Vector3d axis = referenceImage.cameraFromWorldRotation().row( 2 ).transpose();
      for ( const std::string &id : station.imageIds )
      {
        const BlockImage *image = block.findImage( id );
        if ( !image || image->id == reference.id || !image->exterior )
          continue;
        const OrientedImage candidate = block.orientedImage( *image );
        const GroundProjection p = candidate.projectGroundToPixel( ground );
        const Camera &camera = candidate.camera();
        if ( !p.ok() || p.pixelInImage.x() < 20 || p.pixelInImage.y() < 20 || p.pixelInImage.x() > camera.width - 20 || p.pixelInImage.y() > camera.height - 20 )
          continue;
        const double c = axis.dot( candidate.cameraFromWorldRotation().row( 2 ).transpose() );
        if ( c > bestCos )
        {
          bestCos = c;
          best = image;
        }
      }
      return best;
    }
  } // namespace

  RoadTraceRun::RoadTraceRun( const Block &block, const TraceSeed &seed, const RoadTraceOptions &options, const GreyImageSource &images )
    : mBlock( block )
    , mSeed( seed )
    , mOptions( checked( options ) )
    , mImages( images )
    , mSeedImage( block.image( seed.imageId ) )
    , mTrack( block, mSeedImage, mOptions.cameraHeightM )
    , mSequence( mTrack.sequence() )
    , mK( mTrack.seedStation() )
  {
  }

  const RoadTraceOptions &RoadTraceRun::checked( const RoadTraceOptions &options )
  {
    options.check();
    return options;
  }

  void RoadTraceRun::stopWith( TraceStop stop, const std::string &message )
  {
    mOut.stop = stop;
    mOut.message = message;
  }

  RoadTraceSummary RoadTraceRun::run()
  {
    if ( !startAtSeed() )
      return std::move( mOut );
    for ( int stationsDone = 0;; ++stationsDone )
    {
      StationAt at;
      if ( !openStation( at ) )
        break;
      const ReferenceLine line = followInReference( at );
      TracedStation record;
      record.stationId = at.station->id;
      record.referenceImageId = at.referenceImage->id;
      record.partnerImageId = at.partnerImage->id;
      record.method = line.method;
      record.kind = mProfile.kind;
      record.pixelsFollowed = line.followed.line.pixelsFollowed;
      record.bridgedGaps = line.followed.bridgedGaps;
      record.stop = line.followed.line.stop;
      mOut.pixelsFollowed += line.followed.line.pixelsFollowed;
      // a station where the line cannot be followed (it starts in a gap, a car hides it) is passed over:
      // the next one picks the line up from the continuation of what was traced before
      const bool lost = line.followed.line.points.size() < 2;
      const std::string lostMessage = "the line could not be followed in " + at.referenceImage->id + " from (" + std::to_string( mStart.x() ).substr( 0, 6 ) + ", " +
                                      std::to_string( mStart.y() ).substr( 0, 6 ) + ")";
      mConsecutiveLost = lost ? mConsecutiveLost + 1 : 0;
      if ( lost )
        record.stop = TraceStop::NoEdge;
      if ( lost && ( mOut.vertices.empty() || mConsecutiveLost > mOptions.maxStationsPassedOver ) )
      {
        mOut.stations.push_back( record );
        stopWith( TraceStop::NoEdge, lostMessage );
        break;
      }
      StationStereo stereo;
      if ( lost )
        record.partnerMessage = lostMessage;
      else
        stereo = matchInPartner( at, line, record );
      const StationPartSummary joined = appendToRun( at, stereo.vertices );
      record.vertices = joined.ownVertices;
      mOut.stations.push_back( record );
      if ( mOptions.stationTraced )
        mOptions.stationTraced( record, line.followed.line.points, stereo.partnerLine.line.points, mOut.vertices );
      const std::vector<Eigen::Vector3d> groundLine = lineOnGround( at, line.followed.line );
      updateLineDirection( groundLine );
      if ( !mayGoOn( at, stationsDone, groundLine, stereo.partnerStart ) || !linkToNext( at, line.followed.line, groundLine, joined.firstOfStation ) )
        break;
    }
    finish();
    return std::move( mOut );
  }

  //! The seed put onto the line: its start, direction and profile; false (stopped) when there is no line.
  bool RoadTraceRun::startAtSeed()
  {
    const GreyImage reference = mImages( mSeedImage );
    if ( !reference.ok() )
    {
      stopWith( TraceStop::ImageMissing, reference.message );
      return false;
    }
    mReferenceGrey = reference.grey;
    const SeedAnalysis analysis = analyseSeed( *mReferenceGrey, mSeed.pixelInImage, mSeed.directionDeg, mOptions.seed );
    if ( !analysis.ok() )
    {
      stopWith( TraceStop::NoEdge, "in " + mSeedImage.id + ": " + analysis.message );
      return false;
    }
    mStart = analysis.pixelInImage;
    mDirection = analysis.direction;
    mProfile = analysis.profile;
    return true;
  }

  //! The station's reference and partner images, its ground and distance limit; false (stopped) when the partner is missing.
  bool RoadTraceRun::openStation( StationAt &at )
  {
    at.station = &mSequence.at( mK );
    at.referenceImage = mTrack.referenceImageAt( mK );
    if ( !at.referenceImage )
    {
      stopWith( TraceStop::ImageMissing, "station " + at.station->id + " has no oriented image placed in the rig as " + mSeedImage.id + " is" );
      return false;
    }
    at.reference.emplace( mBlock.orientedImage( *at.referenceImage ) );
    at.centre = at.reference->exterior().projectionCentre;
    if ( mPartnerSeedId.empty() && !choosePartner( at ) )
      return false;
    at.partnerImage = imageInRelation( mBlock, *at.station, *at.referenceImage, mPartnerRelation, mPartnerCameraId );
    if ( !at.partnerImage )
    {
      stopWith( TraceStop::NoStereoPartner, "station " + at.station->id + " has no oriented image placed beside " + at.referenceImage->id + " as the stereo partner " +
                mPartnerSeedId + " is beside " + mSeedImage.id );
      return false;
    }
    at.partner.emplace( mBlock.orientedImage( *at.partnerImage ) );
    const GreyImage partner = mImages( *at.partnerImage );
    if ( !partner.ok() )
    {
      stopWith( TraceStop::ImageMissing, partner.message );
      return false;
    }
    at.partnerGrey = partner.grey;
    at.ground = mOptions.groundOfPixel ? mOptions.groundOfPixel : mTrack.roadPlaneOf( 0.5 * ( at.centre.z() + at.partner->exterior().projectionCentre.z() ), at.centre.head<2>() );
    at.rangeLimitM = rangeLimitAt( at.centre );
    prepareFollowing( at );
    return true;
  }

  //! At the seed station: the image that sees the line's first 200 px on the ground (some of them), and where it lies beside the reference.
  bool RoadTraceRun::choosePartner( const StationAt &at )
  {
    const GroundOfPixel single = mOptions.groundOfPixel ? mOptions.groundOfPixel : mTrack.roadPlaneOf( at.centre.z(), at.centre.head<2>() );
    const BlockImage *partner = nullptr;
    bool anyGround = false;
    for ( double s = 0.0; !partner && s <= 200.0; s += 20.0 )
      if ( const std::optional<Eigen::Vector3d> ground = single( *at.reference, mStart + s * mDirection ) )
      {
        anyGround = true;
        partner = partnerSeeing( mBlock, *at.station, *at.referenceImage, *at.reference, *ground );
      }
    if ( !anyGround )
    {
      stopWith( TraceStop::NoStereoPartner, mOptions.groundOfPixel ? "the ground given (the DEM) has no height under the line at the seed in " + at.referenceImage->id +
                                                                         ": it has no data there (nodata or NaN) or does not cover it"
                                                                   : "the line at the seed in " + at.referenceImage->id + " does not reach the road surface under the camera (it lies above the horizon)" );
      return false;
    }
    if ( !partner )
    {
      stopWith( TraceStop::NoStereoPartner, "the seed image " + at.referenceImage->id + " has no stereo partner: no other oriented image of station " + at.station->id + " sees the line" );
      return false;
    }
    mPartnerSeedId = partner->id;
    mPartnerCameraId = partner->cameraId;
    mPartnerRelation = rigRelation( *at.referenceImage, *partner );
    return true;
  }

  /**
   * The distance limit: past the point where the next station takes over,
   * at most maxRangeM (with stations closer than 8 m, still 18 m: a dashed
   * line's next dash must be in reach of the gap bridging).
   */
  double RoadTraceRun::rangeLimitAt( const Eigen::Vector3d &centre ) const
  {
    if ( mStep == 0 && mSequence.size() == 1 )
      return mOptions.maxRangeM;
    double limit = mOptions.maxRangeM;
    for ( const int s : { 1, -1 } )
      if ( ( mStep == 0 || s == mStep ) && mK + s >= 0 && mK + s < mSequence.size() )
        if ( const BlockImage *next = mTrack.referenceImageAt( mK + s ) )
          limit = std::min( limit, std::max( horizontalDistance( next->exterior->projectionCentre, centre ) + mOptions.handoverRangeM + 4.0, 18.0 ) );
    return limit;
  }

  //! The follower's request and ground distance; a stripe's width scaled to the start's range.
  void RoadTraceRun::prepareFollowing( StationAt &at )
  {
    at.follow = mOptions.follow;
    at.follow.groundDistanceM = [&at]( const Eigen::Vector2d &a, const Eigen::Vector2d &b ) -> std::optional<double>
    {
      const std::optional<Eigen::Vector3d> ga = at.ground( *at.reference, a ), gb = at.ground( *at.reference, b );
      return ga && gb ? std::optional<double>( ( *ga - *gb ).norm() ) : std::nullopt;
    };
    at.startGround = at.ground( *at.reference, mStart );
    if ( mProfile.kind != LineKind::Edge && at.startGround )
    {
      const double range = horizontalDistance( *at.startGround, at.centre );
      if ( mWidthTimesRange <= 0 )
        mWidthTimesRange = mProfile.widthPx * range;
      mProfile.widthPx = mWidthTimesRange / std::max( range, 1.0 );
    }
    at.request.start = mStart;
    at.request.direction = mDirection;
    at.request.profile = mProfile;
    at.request.withinLimit = at.withinLimitOf( *at.reference, at.rangeLimitM );
  }

  //! The sigmas scaled by the a posteriori variance factor of the multi-station adjustments (within a factor 4 either way); length and largest sigma.
  void RoadTraceRun::finish()
  {
    // followed in the images but nowhere found in the partner: the stop says that, not where following ended
    const bool endedAsIfTraced = mOut.stop != TraceStop::NoStereoPartner && mOut.stop != TraceStop::ImageMissing && mOut.stop != TraceStop::Cancelled &&
                                 mOut.stop != TraceStop::NoEdge;
    if ( mOut.vertices.size() < 2 && mOut.pixelsFollowed > 0 && endedAsIfTraced )
    {
      std::string why;
      for ( const TracedStation &station : mOut.stations )
        if ( why.empty() && !station.partnerMessage.empty() )
          why = " (at station " + station.stationId + ": " + station.partnerMessage + ")";
      stopWith( TraceStop::NoStereoPartner, "the line was followed in the images through " + std::to_string( mOut.stations.size() ) +
                " station(s), but no vertex of it was found in the stereo partner" + why );
    }
    mOut.sigma0 = std::sqrt( mOut.multiStation.varianceFactor() );
    if ( mOptions.minRedundancyToScaleSigma > 0 && mOut.multiStation.redundancy >= mOptions.minRedundancyToScaleSigma )
    {
      const double factor = std::clamp( mOut.multiStation.varianceFactor(), 0.25, 4.0 );
      for ( TracedVertex &v : mOut.vertices )
      {
        v.covariance *= factor;
        v.sigmaM *= std::sqrt( factor );
      }
      mOut.sigmaScaled = true;
    }
    for ( size_t i = 0; i < mOut.vertices.size(); ++i )
    {
      if ( i > 0 )
        mOut.lengthM += ( mOut.vertices[i].point - mOut.vertices[i - 1].point ).norm();
      mOut.sigmaMaxM = std::max( mOut.sigmaMaxM, mOut.vertices[i].sigmaM.maxCoeff() );
    }
  }

} // namespace geostation
