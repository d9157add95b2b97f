/***************************************************************************
  roadtracesteps.cpp - the steps of a station's tracing: the line followed
  in the reference image, found in the partner, appended to the run's line
  and linked to the next station (roadtracerun.h)
 ***************************************************************************/
#include "tracing/roadtracerun.h"
#include "tracing/trackgeometry.h"

#include <algorithm>
#include <cmath>

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

  //! Before the first handover: the neighbour in time (+1, then -1) that lies ahead along the line; 0 if neither.
  int RoadTraceRun::stepAlongLine( const Eigen::Vector3d &centre ) const
  {
    for ( const int s : { 1, -1 } )
      if ( mK + s >= 0 && mK + s < mSequence.size() )
        if ( const BlockImage *n = mTrack.referenceImageAt( mK + s ); n &&
             ( n->exterior->projectionCentre - centre ).dot( mLineDirection ) > 0 )
          return s;
    return 0;
  }

  /**
   * The dynamic link (§6.5.3) to the next station ahead along the line;
   * where the line is not found in its image (hidden there by a car or a
   * shadow's edge), the stations after it are tried, as many as may be
   * passed over. False (stopped) at the end of the run or of the line.
   */
  bool RoadTraceRun::linkToNext( const StationAt &at, const FollowResult &followed, const std::vector<Eigen::Vector3d> &groundLine, size_t firstOfStation )
  {
    const std::string &id = at.station->id;
    const int nextStep = mStep != 0 ? mStep : stepAlongLine( at.centre );
    if ( nextStep == 0 )
    {
      if ( mK + 1 >= mSequence.size() && mK - 1 < 0 )
        stopWith( TraceStop::EndOfRun, "the run has no further station" );
      else
        stopWith( TraceStop::StationsOutOfOrder, "neither neighbour of station " + id + " in time order lies ahead along the line: the run's stations are out of order" );
      return false;
    }
    if ( mK + nextStep < 0 || mK + nextStep >= mSequence.size() )
    {
      stopWith( TraceStop::EndOfRun, "the line was traced to the end of the run (station " + id + ")" );
      return false;
    }
    const SequenceStation &nextStation = mSequence.at( mK + nextStep );
    const BlockImage *nextImage = mTrack.referenceImageAt( mK + nextStep );
    if ( !nextImage )
    {
      stopWith( TraceStop::ImageMissing, "station " + nextStation.id + " has no oriented image placed in the rig as " + mSeedImage.id + " is" );
      return false;
    }
    // in order: the next station continues the way the run has gone so far (or, at the first step, along the line)
    const Eigen::Vector3d runDirection = mPreviousCentre ? Eigen::Vector3d( at.centre - *mPreviousCentre ) : mLineDirection;
    if ( ( nextImage->exterior->projectionCentre - at.centre ).dot( runDirection ) <= 0 )
    {
      stopWith( TraceStop::StationsOutOfOrder, "station " + nextStation.id + " does not lie ahead of station " + id + " along the line: the run's stations are out of order" );
      return false;
    }
    const GreyImage next = mImages( *nextImage );
    if ( !next.ok() )
    {
      stopWith( TraceStop::ImageMissing, next.message );
      return false;
    }
    std::shared_ptr<const cv::Mat> nextGrey = next.grey;
    mStep = nextStep;
    std::optional<DynamicLink> linked = linkTo( at, *nextImage, *nextGrey, groundLine, firstOfStation );
    int skip = 1;
    for ( int further = 2; !linked && further <= 1 + mOptions.maxStationsPassedOver; ++further )
    {
      const int index = mK + further * mStep;
      if ( index < 0 || index >= mSequence.size() )
        break;
      const BlockImage *laterImage = mTrack.referenceImageAt( index );
      if ( !laterImage || ( laterImage->exterior->projectionCentre - at.centre ).dot( runDirection ) <= 0 )
        break;
      const GreyImage later = mImages( *laterImage );
      if ( !later.ok() )
        break;
      const std::shared_ptr<const cv::Mat> laterGrey = later.grey;
      if ( ( linked = linkTo( at, *laterImage, *laterGrey, groundLine, firstOfStation ) ) )
      {
        skip = further;
        nextGrey = laterGrey;
        mOut.stationsPassedOver += further - 1;
      }
    }
    if ( !linked )
    {
      const TraceStop why = followed.stop == TraceStop::GapTooLarge || followed.stop == TraceStop::DirectionChange ? followed.stop : TraceStop::EndOfLine;
      stopWith( why, "the line was not found in " + nextImage->id + " ahead of its last vertex (station " + id + "): " +
                ( why == TraceStop::GapTooLarge ? "the gap is too large" : why == TraceStop::DirectionChange ? "it turns too sharply; the operator is needed" : "the line ends or is hidden" ) );
      return false;
    }
    mStart = linked->start;
    mDirection = linked->direction;
    mKeep = linked->keep;
    mPreviousCentre = at.centre;
    mK += skip * mStep;
    mReferenceGrey = nextGrey;
    return true;
  }

  //! The line's start in a later station's image (dynamiclink.h), or nothing.
  std::optional<DynamicLink> RoadTraceRun::linkTo( const StationAt &at, const BlockImage &nextImage, const cv::Mat &nextGrey, const std::vector<Eigen::Vector3d> &groundLine,
                                                 size_t firstOfStation ) const
  {
    const OrientedImage next = mBlock.orientedImage( nextImage );
    const Eigen::Vector3d nextCentre = next.exterior().projectionCentre;
    DynamicLinkInput link;
    link.reference = &*at.reference;
    link.referenceGrey = mReferenceGrey.get();
    link.next = &next;
    link.nextGrey = &nextGrey;
    link.nextGround = mOptions.groundOfPixel ? mOptions.groundOfPixel : mTrack.roadPlaneOf( nextCentre.z(), nextCentre.head<2>() );
    link.vertices = &mOut.vertices;
    link.firstOfStation = firstOfStation;
    link.groundLine = &groundLine;
    link.lineDirection = mLineDirection;
    link.trajectory = &mTrack.trajectory();
    link.step = mStep;
    link.profile = mProfile;
    link.widthTimesRange = mWidthTimesRange;
    return linkToNextStation( link, mOptions );
  }

} // namespace geostation
