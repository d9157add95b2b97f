/***************************************************************************
  roadtracer.cpp - one click, the whole run traced (thesis §6.5)
 ***************************************************************************/
#include "tracing/roadtracer.h"
#include "tracing/dynamiclink.h"
#include "tracing/runline.h"
#include "tracing/stationstereo.h"
#include "tracing/trackgeometry.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <set>
#include <stdexcept>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "workstation/stationsequence.h"

namespace geostation
{
  namespace
  {
    double horizontalDistance( const Eigen::Vector3d &a, const Eigen::Vector3d &b ) { return ( a - b ).head<2>().norm(); }

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

    //! The image of a station taken by a camera; nullptr if none.
    const BlockImage *stationImage( const Block &block, const SequenceStation &station, const std::string &cameraId )
    {
      for ( const std::string &id : station.imageIds )
        if ( const BlockImage *image = block.findImage( id ); image && image->cameraId == cameraId )
          return image;
      return nullptr;
    }

    //! The station's other oriented image that sees the ground point, its optical axis closest to the reference's.
    const BlockImage *choosePartner( const Block &block, const SequenceStation &station, const BlockImage &reference, const OrientedImage &referenceImage,
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

    //! The pixel polyline's length on the ground, or 0.
    double groundLength( const OrientedImage &image, const std::vector<Eigen::Vector2d> &points, const GroundOfPixel &ground )
    {
      if ( points.size() < 2 )
        return 0.0;
      const std::optional<Eigen::Vector3d> a = ground( image, points.front() ), b = ground( image, points.back() );
      return a && b ? ( *a - *b ).norm() : 0.0;
    }
  }

  void RoadTraceOptions::check() const
  {
    if ( maxStations < 0 )
      throw std::invalid_argument( "the number of stations must be 0 (the whole run) or more" );
    if ( !( maxRangeM > handoverRangeM ) || !( handoverRangeM > 0 ) )
      throw std::invalid_argument( "the distance limit must be larger than the handover range, and both positive" );
    if ( !( cameraHeightM > 0 ) )
      throw std::invalid_argument( "the camera height above the road must be positive" );
    if ( !( vertexSpacingPx >= 2 ) )
      throw std::invalid_argument( "the vertex spacing must be at least 2 px" );
    if ( minRedundancyToScaleSigma < 0 )
      throw std::invalid_argument( "the redundancy for scaling the sigmas must be 0 (never scaled) or more" );
  }

  std::string RoadTraceSummary::methods() const
  {
    std::vector<std::string> names;
    for ( const TracedStation &s : stations )
    {
      const std::string n = traceMethodName( s.method );
      if ( std::find( names.begin(), names.end(), n ) == names.end() )
        names.push_back( n );
    }
    std::string out;
    for ( const std::string &n : names )
      out += ( out.empty() ? "" : "+" ) + n;
    return out;
  }

  RoadTraceSummary traceRoadLine( const Block &block, const TraceSeed &seed, const RoadTraceOptions &options, const GreyImageSource &images )
  {
    options.check();
    const BlockImage &seedImage = block.image( seed.imageId );
    if ( !seedImage.exterior )
      throw std::invalid_argument( "the seed image " + seedImage.id + " is not oriented" );
    const StationSequence sequence( block );
    int k = sequence.indexOf( seedImage.stationId.empty() ? seedImage.id : seedImage.stationId );
    if ( k < 0 )
      throw std::invalid_argument( "the seed image " + seedImage.id + " belongs to no station of the block" );

    // the reference camera's path through the run, in run order
    // (a station out of order - behind the one before - is left out: it would fold the track back on itself)
    std::vector<Eigen::Vector3d> trajectory;
    for ( const SequenceStation &st : sequence.stations() )
      if ( const BlockImage *image = stationImage( block, st, seedImage.cameraId ); image && image->exterior )
      {
        const Eigen::Vector3d &c = image->exterior->projectionCentre;
        if ( trajectory.size() >= 2 && ( c - trajectory.back() ).head<2>().dot( ( trajectory.back() - trajectory[trajectory.size() - 2] ).head<2>() ) <= 0 )
          continue;
        trajectory.push_back( c );
      }
    const std::vector<Eigen::Vector3d> smoothTrack = smoothedHeights( trajectory, 30.0 );
    // the road surface under a point, hung from a camera at `cameraZ` over `cameraXY`: the smoothed track's
    // shape, offset so that the surface is the camera's height below it there
    const auto surfaceHeight = [&smoothTrack, h = options.cameraHeightM]( const Eigen::Vector2d &xy, double cameraZ, const Eigen::Vector2d &cameraXY ) -> std::optional<double>
    {
      const std::optional<double> here = trackSurfaceHeight( smoothTrack, xy, h ), under = trackSurfaceHeight( smoothTrack, cameraXY, 0.0 );
      if ( !here || !under )
        return std::nullopt;
      return *here + ( cameraZ - *under );
    };

    RoadTraceSummary out;
    const auto stopWith = [&]( TraceStop stop, const std::string &message )
    {
      out.stop = stop;
      out.message = message;
    };
    std::string error;
    std::shared_ptr<const cv::Mat> referenceGrey = images( seedImage, error );
    const std::string referenceCamera = seedImage.cameraId;
    std::string partnerCamera;
    Eigen::Vector2d start = seed.pixelInImage, direction;
    LineProfile profile;
    double widthTimesRange = 0.0; // stripes narrow as 1 / range
    size_t keep = 0;              // run vertices kept when the next station's are appended
    int step = 0;                 // +1 or -1 through the run, set at the first handover
    Eigen::Vector3d lineDirection = Eigen::Vector3d::Zero();
    std::optional<Eigen::Vector3d> previousCentre; // the last station's reference camera
    int consecutiveLost = 0;
    std::deque<StationBehind> behind; // the stations traced before, nearest first

    if ( !referenceGrey )
    {
      stopWith( TraceStop::ImageMissing, error );
      return out;
    }
    const SeedAnalysis analysis = analyseSeed( *referenceGrey, seed.pixelInImage, seed.directionDeg, options.seed );
    if ( !analysis.ok )
    {
      stopWith( TraceStop::NoEdge, "in " + seedImage.id + ": " + analysis.message );
      return out;
    }
    start = analysis.pixelInImage;
    direction = analysis.direction;
    profile = analysis.profile;

    for ( int stationsDone = 0;; ++stationsDone )
    {
      const SequenceStation &station = sequence.at( k );
      const BlockImage *referenceImage = stationImage( block, station, referenceCamera );
      const OrientedImage reference = block.orientedImage( *referenceImage );
      const Eigen::Vector3d centre = reference.exterior().projectionCentre;
      // the partner: chosen at the seed station by what sees the start, then the same camera throughout
      // the road surface: the plane under the station, its height then taken from the track where the ray meets it
      const auto roadPlaneOf = [&]( double z, const Eigen::Vector2d &cameraXY ) -> GroundOfPixel
      {
        return [z, cameraXY, h = options.cameraHeightM, &surfaceHeight]( const OrientedImage &image, const Eigen::Vector2d &pixel ) -> std::optional<Eigen::Vector3d>
        {
          std::optional<Eigen::Vector3d> p = roadPlanePoint( image, pixel, z - h );
          for ( int it = 0; it < 2 && p; ++it )
            if ( const std::optional<double> surface = surfaceHeight( p->head<2>(), z, cameraXY ) )
              if ( std::optional<Eigen::Vector3d> q = roadPlanePoint( image, pixel, *surface ) )
                p = q;
          return p;
        };
      };
      if ( partnerCamera.empty() )
      {
        // the line's first 200 px on the ground: some of it must be in view of the partner
        const GroundOfPixel single = options.groundOfPixel ? options.groundOfPixel : roadPlaneOf( centre.z(), centre.head<2>() );
        const BlockImage *partner = nullptr;
        for ( double s = 0.0; !partner && s <= 200.0; s += 20.0 )
          if ( const std::optional<Eigen::Vector3d> ground = single( reference, start + s * direction ) )
            partner = choosePartner( block, station, *referenceImage, reference, *ground );
        if ( !partner )
        {
          stopWith( TraceStop::NoStereoPartner, "the seed image " + referenceImage->id + " has no stereo partner: no other oriented image of station " + station.id + " sees the line" );
          break;
        }
        partnerCamera = partner->cameraId;
      }
      const BlockImage *partnerImage = stationImage( block, station, partnerCamera );
      if ( !partnerImage || !partnerImage->exterior )
      {
        stopWith( TraceStop::NoStereoPartner, "station " + station.id + " has no oriented image of the partner camera " + partnerCamera );
        break;
      }
      const OrientedImage partner = block.orientedImage( *partnerImage );
      const std::shared_ptr<const cv::Mat> partnerGrey = images( *partnerImage, error );
      if ( !partnerGrey )
      {
        stopWith( TraceStop::ImageMissing, error );
        break;
      }
      const GroundOfPixel ground = options.groundOfPixel ? options.groundOfPixel : roadPlaneOf( 0.5 * ( centre.z() + partner.exterior().projectionCentre.z() ), centre.head<2>() );

      // the distance limit: past the point where the next station takes over, at most maxRangeM
      // (with stations closer than 8 m, still 18 m: a dashed line's next dash must be in reach of the gap bridging)
      double rangeLimit = options.maxRangeM;
      for ( const int s : { 1, -1 } )
        if ( ( step == 0 || s == step ) && k + s >= 0 && k + s < sequence.size() )
          if ( const BlockImage *next = stationImage( block, sequence.at( k + s ), referenceCamera ); next && next->exterior )
            rangeLimit = std::min( rangeLimit, std::max( horizontalDistance( next->exterior->projectionCentre, centre ) + options.handoverRangeM + 4.0, 18.0 ) );
      if ( step == 0 && sequence.size() == 1 )
        rangeLimit = options.maxRangeM;
      const auto withinLimitOf = [&]( const OrientedImage &image, double limit )
      {
        return [&image, &ground, centre, limit]( const Eigen::Vector2d &pixel )
        {
          const std::optional<Eigen::Vector3d> g = ground( image, pixel );
          return g && horizontalDistance( *g, centre ) <= limit;
        };
      };
      LineFollowOptions follow = options.follow;
      follow.groundDistanceM = [&]( const Eigen::Vector2d &a, const Eigen::Vector2d &b ) -> std::optional<double>
      {
        const std::optional<Eigen::Vector3d> ga = ground( reference, a ), gb = ground( reference, b );
        return ga && gb ? std::optional<double>( ( *ga - *gb ).norm() ) : std::nullopt;
      };
      const std::optional<Eigen::Vector3d> startGround = ground( reference, start );
      if ( profile.kind != LineKind::Edge && startGround )
      {
        const double range = horizontalDistance( *startGround, centre );
        if ( widthTimesRange <= 0 )
          widthTimesRange = profile.widthPx * range;
        profile.widthPx = widthTimesRange / std::max( range, 1.0 );
      }

      // follow in the reference image: the method asked for, or auto's choice
      FollowRequest request;
      request.start = start;
      request.direction = direction;
      request.profile = profile;
      request.withinLimit = withinLimitOf( reference, rangeLimit );
      // auto: polynomial strips first (they bridge dashes, wear and shadows and are the most precise in the
      // tests); where they cover less than half the way, the skeleton (stripes) or least squares (edges)
      TraceMethod method = options.method == TraceMethod::Auto ? TraceMethod::Polynomial : options.method;
      // a road line runs with the road: what leaves the corridor through the start is cut off
      const auto keepInCourse = [&]( LineFollowResult result )
      {
        if ( !startGround || options.courseHalfWidthM <= 0 )
          return result;
        std::vector<std::optional<Eigen::Vector3d>> onGround;
        for ( const Eigen::Vector2d &p : result.line.points )
          onGround.push_back( ground( reference, p ) );
        const size_t n = pointsInCourse( trajectory, *startGround, onGround, options.courseHalfWidthM, options.courseSlope );
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
      };
      LineFollowResult followed = keepInCourse( followLine( *referenceGrey, request, method, follow ) );
      if ( options.method == TraceMethod::Auto && startGround )
      {
        const double wanted = rangeLimit - horizontalDistance( *startGround, centre );
        if ( groundLength( reference, followed.line.points, ground ) < 0.5 * wanted && followed.line.stop != TraceStop::LeftImage )
        {
          const TraceMethod other = profile.kind == LineKind::Edge ? TraceMethod::LeastSquares : TraceMethod::Directional;
          LineFollowResult second = keepInCourse( followLine( *referenceGrey, request, other, follow ) );
          if ( groundLength( reference, second.line.points, ground ) > groundLength( reference, followed.line.points, ground ) )
          {
            followed = second;
            method = other;
          }
        }
      }
      // a gap between the line so far and this station's start (the last station lost the line early): followed
      // back from the start too, towards the camera, where this station sees the line best
      if ( startGround && keep > 0 && keep <= out.vertices.size() && followed.line.points.size() >= 2 &&
           horizontalDistance( *startGround, out.vertices[keep - 1].point ) > options.backfillGapM )
      {
        FollowRequest backwardRequest = request;
        backwardRequest.direction = -request.direction;
        if ( profile.kind == LineKind::Edge )
          backwardRequest.profile.polarity = -profile.polarity;
        // (auto: polynomial strips, the most precise; the skeleton's end pixels stray)
        const LineFollowResult backward = keepInCourse( followLine( *referenceGrey, backwardRequest, options.method == TraceMethod::Auto ? TraceMethod::Polynomial : method, follow ) );
        followed.line.pixelsFollowed += backward.line.pixelsFollowed;
        joinBackward( backward.line, followed.line );
      }
      TracedStation record;
      record.stationId = station.id;
      record.referenceImageId = referenceImage->id;
      record.partnerImageId = partnerImage->id;
      record.method = method;
      record.kind = profile.kind;
      record.pixelsFollowed = followed.line.pixelsFollowed;
      record.bridgedGaps = followed.bridgedGaps;
      record.stop = followed.line.stop;
      out.pixelsFollowed += followed.line.pixelsFollowed;
      // a station where the line cannot be followed (it starts in a gap, a car hides it) is passed over:
      // the next one picks the line up from the continuation of what was traced before
      const bool lost = followed.line.points.size() < 2;
      const std::string lostMessage = "the line could not be followed in " + referenceImage->id + " from (" + std::to_string( start.x() ).substr( 0, 6 ) + ", " +
                                      std::to_string( start.y() ).substr( 0, 6 ) + ")";
      consecutiveLost = lost ? consecutiveLost + 1 : 0;
      if ( lost && ( out.vertices.empty() || consecutiveLost > options.maxStationsPassedOver ) )
      {
        out.stations.push_back( record );
        stopWith( TraceStop::NoEdge, lostMessage );
        break;
      }
      std::vector<LineVertex3d> vertices;
      LineFollowResult partnerLine;
      StartMatch partnerStart;
      if ( !lost )
      {
        // the partner: start by correlation along the epipolar curve, then the same method; 3-D vertices
        StationStereoInput input;
        input.stationId = station.id;
        input.reference = { referenceImage->id, &reference, referenceGrey.get() };
        input.partner = { partnerImage->id, &partner, partnerGrey.get() };
        input.ground = ground;
        input.referenceLine = followed.line;
        input.request = request;
        input.method = method;
        input.follow = follow;
        input.partnerWithinLimit = withinLimitOf( partner, rangeLimit + 3.0 );
        input.profile = profile;
        input.widthTimesRange = widthTimesRange;
        input.lineDirection = lineDirection;
        for ( const StationBehind &b : behind )
          input.behind.push_back( b.view() );
        StationStereo stereo = traceStationStereo( input, options );
        vertices = std::move( stereo.vertices );
        partnerLine = std::move( stereo.partnerLine );
        partnerStart = stereo.partnerStart;
        out.multiStation.vertices += stereo.multiStation.vertices;
        out.multiStation.observations += stereo.multiStation.observations;
        out.multiStation.rejected += stereo.multiStation.rejected;
        out.multiStation.dropped += stereo.multiStation.dropped;
        out.multiStation.unconfirmed += stereo.multiStation.unconfirmed;
        out.multiStation.weightedSquares += stereo.multiStation.weightedSquares;
        out.multiStation.redundancy += stereo.multiStation.redundancy;
        if ( partnerStart.ok )
        {
          record.partnerScore = partnerStart.score;
          if ( options.stationsBehind > 0 )
          {
            behind.push_front( { station.id, { referenceImage->id, partnerImage->id }, { reference, partner }, { referenceGrey, partnerGrey } } );
            if ( behind.size() > static_cast<size_t>( options.stationsBehind ) )
              behind.pop_back();
          }
        }
        else
          record.partnerMessage = partnerStart.message;
      }
      else
        record.partnerMessage = lostMessage;

      // into the run's line
      StationPart part;
      part.stationId = station.id;
      part.referenceImageId = referenceImage->id;
      part.partnerImageId = partnerImage->id;
      part.runAlong = previousCentre ? Eigen::Vector3d( centre - *previousCentre ) : Eigen::Vector3d( reference.cameraFromWorldRotation().row( 2 ).transpose() * -1.0 );
      part.keep = keep;
      part.trajectory = &trajectory;
      if ( !options.groundOfPixel )
        part.surfaceHeight = [&]( const Eigen::Vector3d &p ) { return surfaceHeight( p.head<2>(), centre.z(), centre.head<2>() ); };
      const StationPartSummary joined = appendStationPart( out.vertices, vertices, part, options );
      const size_t firstOfStation = joined.firstOfStation;
      out.heightOutliers += joined.heightOutliers;
      out.lateralOutliers += joined.lateralOutliers;
      record.vertices = joined.ownVertices;
      out.stations.push_back( record );
      if ( options.stationTraced )
        options.stationTraced( record, followed.line.points, partnerLine.line.points, out.vertices );
      if ( lost )
        record.stop = TraceStop::NoEdge;
      // the line on the ground so far: the run's vertices, or (before any) the reference line on the road surface
      std::vector<Eigen::Vector3d> groundLine;
      for ( const TracedVertex &v : out.vertices )
        groundLine.push_back( v.point );
      if ( groundLine.size() < 2 )
      {
        // (a lone vertex is not mixed with the line on the road surface: their difference is no direction)
        groundLine.clear();
        for ( const Eigen::Vector2d &p : followed.line.points )
          if ( const std::optional<Eigen::Vector3d> g = ground( reference, p ) )
            groundLine.push_back( *g );
      }
      // its direction over the last 20 m
      if ( groundLine.size() >= 2 )
      {
        size_t from = groundLine.size() - 1;
        while ( from > 0 && ( groundLine.back() - groundLine[from - 1] ).head<2>().norm() < 20.0 )
          --from;
        if ( ( groundLine.back() - groundLine[from] ).norm() > 0.2 )
          lineDirection = ( groundLine.back() - groundLine[from] ).normalized();
      }

      if ( options.progress && !options.progress( sequence.size() > 1 ? static_cast<double>( stationsDone + 1 ) / sequence.size() : 1.0, "station " + station.id ) )
      {
        stopWith( TraceStop::Cancelled, "tracing was cancelled after station " + station.id );
        break;
      }
      if ( options.maxStations > 0 && stationsDone + 1 >= options.maxStations )
      {
        stopWith( TraceStop::MaxStations, std::to_string( options.maxStations ) + " stations traced, as asked" );
        break;
      }
      if ( groundLine.size() < 2 || lineDirection.isZero() )
      {
        stopWith( TraceStop::NoEdge, "no vertex of " + referenceImage->id + " could be matched in " + partnerImage->id +
                  ( partnerStart.ok ? std::string() : " (" + partnerStart.message + ")" ) );
        break;
      }

      // dynamic link: the next station ahead along the line
      int nextStep = step;
      if ( nextStep == 0 )
        for ( const int s : { 1, -1 } )
          if ( k + s >= 0 && k + s < sequence.size() )
            if ( const BlockImage *n = stationImage( block, sequence.at( k + s ), referenceCamera ); n && n->exterior &&
                 ( n->exterior->projectionCentre - centre ).dot( lineDirection ) > 0 )
            {
              nextStep = s;
              break;
            }
      if ( nextStep == 0 )
      {
        if ( k + 1 >= sequence.size() && k - 1 < 0 )
          stopWith( TraceStop::EndOfRun, "the run has no further station" );
        else
          stopWith( TraceStop::StationsOutOfOrder, "neither neighbour of station " + station.id + " in time order lies ahead along the line: the run's stations are out of order" );
        break;
      }
      if ( k + nextStep < 0 || k + nextStep >= sequence.size() )
      {
        stopWith( TraceStop::EndOfRun, "the line was traced to the end of the run (station " + station.id + ")" );
        break;
      }
      const SequenceStation &nextStation = sequence.at( k + nextStep );
      const BlockImage *nextImage = stationImage( block, nextStation, referenceCamera );
      if ( !nextImage || !nextImage->exterior )
      {
        stopWith( TraceStop::ImageMissing, "station " + nextStation.id + " has no oriented image of camera " + referenceCamera );
        break;
      }
      // in order: the next station continues the way the run has gone so far (or, at the first step, along the line)
      const Eigen::Vector3d runDirection = previousCentre ? Eigen::Vector3d( centre - *previousCentre ) : lineDirection;
      if ( ( nextImage->exterior->projectionCentre - centre ).dot( runDirection ) <= 0 )
      {
        stopWith( TraceStop::StationsOutOfOrder, "station " + nextStation.id + " does not lie ahead of station " + station.id + " along the line: the run's stations are out of order" );
        break;
      }
      std::shared_ptr<const cv::Mat> nextGrey = images( *nextImage, error );
      if ( !nextGrey )
      {
        stopWith( TraceStop::ImageMissing, error );
        break;
      }
      step = nextStep;
      // the dynamic link; where the line is not found in the next station's image (hidden there by a car or a
      // shadow's edge), the stations after it are tried, as many as may be passed over
      const auto linkTo = [&]( const BlockImage &nextImage, const cv::Mat &nextGreyImage ) -> std::optional<DynamicLink>
      {
        const OrientedImage next = block.orientedImage( nextImage );
        const Eigen::Vector3d nextCentre = next.exterior().projectionCentre;
        DynamicLinkInput link;
        link.reference = &reference;
        link.referenceGrey = referenceGrey.get();
        link.next = &next;
        link.nextGrey = &nextGreyImage;
        link.nextGround = options.groundOfPixel ? options.groundOfPixel : roadPlaneOf( nextCentre.z(), nextCentre.head<2>() );
        link.vertices = &out.vertices;
        link.firstOfStation = firstOfStation;
        link.groundLine = &groundLine;
        link.lineDirection = lineDirection;
        link.trajectory = &trajectory;
        link.step = step;
        link.profile = profile;
        link.widthTimesRange = widthTimesRange;
        return linkToNextStation( link, options );
      };
      std::optional<DynamicLink> linked = linkTo( *nextImage, *nextGrey );
      int skip = 1;
      for ( int further = 2; !linked && further <= 1 + options.maxStationsPassedOver; ++further )
      {
        const int index = k + further * step;
        if ( index < 0 || index >= sequence.size() )
          break;
        const BlockImage *laterImage = stationImage( block, sequence.at( index ), referenceCamera );
        if ( !laterImage || !laterImage->exterior || ( laterImage->exterior->projectionCentre - centre ).dot( runDirection ) <= 0 )
          break;
        std::string laterError;
        const std::shared_ptr<const cv::Mat> laterGrey = images( *laterImage, laterError );
        if ( !laterGrey )
          break;
        if ( ( linked = linkTo( *laterImage, *laterGrey ) ) )
        {
          skip = further;
          nextGrey = laterGrey;
          out.stationsPassedOver += further - 1;
        }
      }
      if ( linked )
      {
        start = linked->start;
        direction = linked->direction;
        keep = linked->keep;
      }
      else
      {
        const TraceStop why = followed.line.stop == TraceStop::GapTooLarge || followed.line.stop == TraceStop::DirectionChange ? followed.line.stop : TraceStop::EndOfLine;
        stopWith( why, "the line was not found in " + nextImage->id + " ahead of its last vertex (station " + station.id + "): " +
                  ( why == TraceStop::GapTooLarge ? "the gap is too large" : why == TraceStop::DirectionChange ? "it turns too sharply; the operator is needed" : "the line ends or is hidden" ) );
        break;
      }
      previousCentre = centre;
      k += skip * step;
      referenceGrey = nextGrey;
    }

    // the a posteriori variance factor of the multi-station adjustments (within a factor 4 either way)
    out.sigma0 = std::sqrt( out.multiStation.varianceFactor() );
    if ( options.minRedundancyToScaleSigma > 0 && out.multiStation.redundancy >= options.minRedundancyToScaleSigma )
    {
      const double factor = std::clamp( out.multiStation.varianceFactor(), 0.25, 4.0 );
      for ( TracedVertex &v : out.vertices )
      {
        v.covariance *= factor;
        v.sigmaM *= std::sqrt( factor );
      }
      out.sigmaScaled = true;
    }
    for ( size_t i = 0; i < out.vertices.size(); ++i )
    {
      if ( i > 0 )
        out.lengthM += ( out.vertices[i].point - out.vertices[i - 1].point ).norm();
      out.sigmaMaxM = std::max( out.sigmaMaxM, out.vertices[i].sigmaM.maxCoeff() );
    }
    return out;
  }

} // namespace geostation
