/***************************************************************************
  roadtracerun.cpp - a road line traced through a run: set-up, the loop
  over the stations, a station's images, the steps of its tracing, and
  the finish (roadtracerun.h)
 ***************************************************************************/
#include "tracing/roadtracerun.h"
#include "tracing/stationhandover.h"
#include "tracing/trackgeometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

namespace geostation
{
  namespace
  {
    //! The pixel polyline's length on the ground, or 0.
    double groundLength( const OrientedImage &image, const std::vector<Eigen::Vector2d> &points, const GroundOfPixel &ground )
    {
      if ( points.size() < 2 )
        return 0.0;
      const std::optional<Eigen::Vector3d> a = ground( image, points.front() ), b = ground( image, points.back() );
      return a && b ? ( *a - *b ).norm() : 0.0;
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
        partner = stereoPartnerSeeing( mBlock, *at.station, *at.referenceImage, *ground );
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

  //! A road line runs with the road: what leaves the corridor through the start is cut off.
  LineFollowResult RoadTraceRun::keepInCourse( const StationAt &at, LineFollowResult result ) const
  {
    if ( !at.startGround || mOptions.courseHalfWidthM <= 0 )
      return result;
    std::vector<std::optional<Eigen::Vector3d>> onGround;
    for ( const Eigen::Vector2d &p : result.line.points )
      onGround.push_back( at.ground( *at.reference, p ) );
    const size_t n = pointsInCourse( mTrack.trajectory(), *at.startGround, onGround, mOptions.courseHalfWidthM, mOptions.courseSlope );
    if ( n < result.line.points.size() )
    {
      result.line.points.resize( n );
      result.line.sigmaPx.resize( std::min( n, result.line.sigmaPx.size() ) );
      result.line.bridged.resize( std::min( n, result.line.bridged.size() ) );
      result.line.stop = TraceStop::DirectionChange;
      if ( n >= 2 )
        result.line.direction = ( result.line.points[n - 1] - result.line.points[n - 2] ).normalized();
    }
    return result;
  }

  /**
   * The line in the reference image: the method asked for, or auto's
   * choice (autoMethodOrder(): for paint the polynomial strips, for edges
   * and dark bands least squares), the next methods in auto's order tried
   * while the line covers less than half the way.
   */
  ReferenceLine RoadTraceRun::followInReference( const StationAt &at ) const
  {
    const bool automatic = mOptions.method == TraceMethod::Auto;
    ReferenceLine line;
    const std::vector<TraceMethod> order = autoMethodOrder( mProfile );
    line.method = automatic ? order.front() : mOptions.method;
    line.followed = keepInCourse( at, followLine( *mReferenceGrey, at.request, line.method, at.follow ) );
    const OrientedImage &reference = *at.reference;
    if ( automatic && at.startGround )
    {
      // while the line covers less than half the way, the other methods are tried in turn; the longest is kept
      const double wanted = at.rangeLimitM - horizontalDistance( *at.startGround, at.centre );
      const std::vector<TraceMethod> others( order.begin() + 1, order.end() );
      double length = groundLength( reference, line.followed.line.points, at.ground );
      for ( const TraceMethod other : others )
      {
        if ( length >= 0.5 * wanted || line.followed.line.stop == TraceStop::LeftImage )
          break;
        LineFollowResult next = keepInCourse( at, followLine( *mReferenceGrey, at.request, other, at.follow ) );
        const double nextLength = groundLength( reference, next.line.points, at.ground );
        if ( nextLength > length )
        {
          line.followed = std::move( next );
          line.method = other;
          length = nextLength;
        }
      }
    }
    // a gap between the line so far and this station's start (the last station lost the line early): followed
    // back from the start too, towards the camera, where this station sees the line best
    if ( at.startGround && mKeep > 0 && mKeep <= mOut.vertices.size() && line.followed.line.points.size() >= 2 &&
         horizontalDistance( *at.startGround, mOut.vertices[mKeep - 1].point ) > mOptions.backfillGapM )
    {
      FollowRequest backwardRequest = at.request;
      backwardRequest.direction = -at.request.direction;
      if ( mProfile.kind == LineKind::Edge )
        backwardRequest.profile.polarity = -mProfile.polarity;
      // (auto: polynomial strips, the most precise; the skeleton's end pixels stray)
      const LineFollowResult backward = keepInCourse( at, followLine( *mReferenceGrey, backwardRequest, automatic ? TraceMethod::Polynomial : line.method, at.follow ) );
      line.followed.line.pixelsFollowed += backward.line.pixelsFollowed;
      joinBackward( backward.line, line.followed.line );
    }
    return line;
  }

  //! The partner's start by correlation along the epipolar curve, then the same method; the station's 3-D vertices.
  StationStereo RoadTraceRun::matchInPartner( const StationAt &at, const ReferenceLine &line, TracedStation &record )
  {
    StationStereoInput input;
    input.stationId = at.station->id;
    input.reference = { at.referenceImage->id, &*at.reference, mReferenceGrey.get() };
    input.partner = { at.partnerImage->id, &*at.partner, at.partnerGrey.get() };
    input.ground = at.ground;
    input.referenceLine = line.followed.line;
    input.request = at.request;
    input.method = line.method;
    input.follow = at.follow;
    input.partnerWithinLimit = at.withinLimitOf( *at.partner, at.rangeLimitM + 3.0 );
    input.profile = mProfile;
    input.widthTimesRange = mWidthTimesRange;
    input.lineDirection = mLineDirection;
    for ( const StationBehind &b : mBehind )
      input.behind.push_back( b.view() );
    StationStereo stereo = traceStationStereo( input, mOptions );
    MultiStationSummary &all = mOut.multiStation;
    all.vertices += stereo.multiStation.vertices;
    all.observations += stereo.multiStation.observations;
    all.rejected += stereo.multiStation.rejected;
    all.dropped += stereo.multiStation.dropped;
    all.unconfirmed += stereo.multiStation.unconfirmed;
    all.weightedSquares += stereo.multiStation.weightedSquares;
    all.redundancy += stereo.multiStation.redundancy;
    if ( !stereo.partnerStart.ok() )
    {
      record.partnerMessage = stereo.partnerStart.message;
      return stereo;
    }
    record.partnerScore = stereo.partnerStart.score;
    if ( mOptions.stationsBehind > 0 )
    {
      mBehind.push_front( { at.station->id, { at.referenceImage->id, at.partnerImage->id }, { *at.reference, *at.partner }, { mReferenceGrey, at.partnerGrey } } );
      if ( mBehind.size() > static_cast<size_t>( mOptions.stationsBehind ) )
        mBehind.pop_back();
    }
    return stereo;
  }

  //! The station's vertices into the run's line (runline.h).
  StationPartSummary RoadTraceRun::appendToRun( const StationAt &at, const std::vector<LineVertex3d> &vertices )
  {
    StationPart part;
    part.stationId = at.station->id;
    part.referenceImageId = at.referenceImage->id;
    part.partnerImageId = at.partnerImage->id;
    part.runAlong = mPreviousCentre ? Eigen::Vector3d( at.centre - *mPreviousCentre ) : Eigen::Vector3d( at.reference->cameraFromWorldRotation().row( 2 ).transpose() * -1.0 );
    part.keep = mKeep;
    part.trajectory = &mTrack.trajectory();
    if ( !mOptions.groundOfPixel )
      part.surfaceHeight = [this, &at]( const Eigen::Vector3d &p ) { return mTrack.surfaceHeight( p.head<2>(), at.centre.z(), at.centre.head<2>() ); };
    const StationPartSummary joined = appendStationPart( mOut.vertices, vertices, part, mOptions );
    mOut.heightOutliers += joined.heightOutliers;
    mOut.lateralOutliers += joined.lateralOutliers;
    return joined;
  }

  //! The line on the ground so far: the run's vertices, or (before any) the reference line on the road surface.
  std::vector<Eigen::Vector3d> RoadTraceRun::lineOnGround( const StationAt &at, const FollowResult &followed ) const
  {
    std::vector<Eigen::Vector3d> groundLine;
    for ( const TracedVertex &v : mOut.vertices )
      groundLine.push_back( v.point );
    if ( groundLine.size() >= 2 )
      return groundLine;
    // (a lone vertex is not mixed with the line on the road surface: their difference is no direction)
    groundLine.clear();
    for ( const Eigen::Vector2d &p : followed.points )
      if ( const std::optional<Eigen::Vector3d> g = at.ground( *at.reference, p ) )
        groundLine.push_back( *g );
    return groundLine;
  }

  //! The line's direction over its last 20 m on the ground (kept where that is shorter than 0.2 m).
  void RoadTraceRun::updateLineDirection( const std::vector<Eigen::Vector3d> &groundLine )
  {
    if ( groundLine.size() < 2 )
      return;
    size_t from = groundLine.size() - 1;
    while ( from > 0 && ( groundLine.back() - groundLine[from - 1] ).head<2>().norm() < 20.0 )
      --from;
    if ( ( groundLine.back() - groundLine[from] ).norm() > 0.2 )
      mLineDirection = ( groundLine.back() - groundLine[from] ).normalized();
  }

  //! Progress and cancel, the station limit, and a line to go on with; false (stopped) otherwise.
  bool RoadTraceRun::mayGoOn( const StationAt &at, int stationsDone, const std::vector<Eigen::Vector3d> &groundLine, const StartMatch &partnerStart )
  {
    const std::string &id = at.station->id;
    if ( !mOptions.progress.report( mSequence.size() > 1 ? static_cast<double>( stationsDone + 1 ) / mSequence.size() : 1.0, "station " + id ) )
    {
      stopWith( TraceStop::Cancelled, "tracing was cancelled after station " + id );
      return false;
    }
    if ( mOptions.maxStations > 0 && stationsDone + 1 >= mOptions.maxStations )
    {
      stopWith( TraceStop::MaxStations, std::to_string( mOptions.maxStations ) + " stations traced, as asked" );
      return false;
    }
    if ( groundLine.size() < 2 || mLineDirection.isZero() )
    {
      stopWith( TraceStop::NoEdge, "no vertex of " + at.referenceImage->id + " could be matched in " + at.partnerImage->id +
                ( partnerStart.ok() ? std::string() : " (" + partnerStart.message + ")" ) );
      return false;
    }
    return true;
  }

  //! The line handed over to the next station ahead along it (stationhandover.h); false (stopped) at the end of the run or of the line.
  bool RoadTraceRun::linkToNext( const StationAt &at, const FollowResult &followed, const std::vector<Eigen::Vector3d> &groundLine, size_t firstOfStation )
  {
    HandoverInput in;
    in.block = &mBlock;
    in.track = &mTrack;
    in.images = &mImages;
    in.seedImageId = mSeedImage.id;
    in.station = mK;
    in.step = mStep;
    in.reference = &*at.reference;
    in.referenceGrey = mReferenceGrey.get();
    in.previousCentre = mPreviousCentre;
    in.followed = &followed;
    in.vertices = &mOut.vertices;
    in.firstOfStation = firstOfStation;
    in.groundLine = &groundLine;
    in.lineDirection = mLineDirection;
    in.profile = mProfile;
    in.widthTimesRange = mWidthTimesRange;
    const Handover handover = handOverToNextStation( in, mOptions );
    if ( !handover.ok() )
    {
      stopWith( *handover.stop, handover.message );
      return false;
    }
    mOut.stationsPassedOver += handover.passedOver;
    mStart = handover.link.start;
    mDirection = handover.link.direction;
    mKeep = handover.link.keep;
    mStep = handover.step;
    mPreviousCentre = at.centre;
    mK = handover.station;
    mReferenceGrey = handover.grey;
    return true;
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
