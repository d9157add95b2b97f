/***************************************************************************
  dynamiclink.cpp
 ***************************************************************************/
#include "tracing/dynamiclink.h"

#include <algorithm>
#include <cmath>

#include "tracing/handovermatcher.h"
#include "tracing/trackgeometry.h"

namespace geostation
{

  namespace
  {
    double horizontalDistance( const Eigen::Vector3d &a, const Eigen::Vector3d &b ) { return ( a - b ).head<2>().norm(); }
  }

  std::optional<DynamicLink> linkToNextStation( const DynamicLinkInput &in, const RoadTraceOptions &options )
  {
    const OrientedImage &next = *in.next;
    const std::vector<TracedVertex> &vertices = *in.vertices;
    const std::vector<Eigen::Vector3d> &groundLine = *in.groundLine, &trajectory = *in.trajectory;
    const Eigen::Vector3d &lineDirection = in.lineDirection;
    const size_t firstOfStation = in.firstOfStation;
    const int step = in.step;
    const LineProfile &profile = in.profile;
    const double widthTimesRange = in.widthTimesRange;
    const GroundOfPixel &nextGround = in.nextGround;
    const Eigen::Vector3d nextCentre = next.exterior().projectionCentre;
    // the line's direction at a point: the chord over its last 20 m turned with the track (on the 220 m curve the
    // chord is 2.6 degrees off the line's tangent at its end, more beyond it)
    size_t chordFrom = groundLine.size() - 1;
    while ( chordFrom > 0 && horizontalDistance( groundLine.back(), groundLine[chordFrom - 1] ) < 20.0 )
      --chordFrom;
    const Eigen::Vector3d chordMiddle = 0.5 * ( groundLine[chordFrom] + groundLine.back() );
    const auto directionAt = [&]( const Eigen::Vector3d &point ) { return lineDirectionAt( trajectory, lineDirection, chordMiddle, point ); };
    // candidates: this station's vertices, then the line's straight continuation across a gap
    std::vector<std::pair<Eigen::Vector3d, size_t>> candidates; // point, vertices kept if taken
    for ( size_t i = firstOfStation; i < vertices.size(); ++i )
      candidates.push_back( { vertices[i].point, i } );
    // (past the next station's camera by the gap limit: a station whose vertices failed is bridged too)
    {
      const double reach = horizontalDistance( groundLine.back(), next.exterior().projectionCentre ) + options.follow.maxGapM + options.handoverRangeM;
      // (a last vertex that strays from the line's offset from the track over its last 10 m - the follower
      // slid onto a parallel edge at its far end - does not lead it astray: the recent offset is kept)
      std::optional<double> offset = recentTrackOffset( trajectory, groundLine, 10.0 );
      const std::optional<TrackCoordinates> own = trackCoordinates( trajectory, groundLine.back().head<2>() );
      // (with the lateral check off, maxLateralStepM <= 0, the line's own last vertex leads)
      if ( offset && ( options.maxLateralStepM <= 0 || ( own && std::abs( *offset - own->leftOffsetM ) <= options.maxLateralStepM ) ) )
        offset.reset();
      for ( const Eigen::Vector3d &p : trajectoryContinuation( trajectory, groundLine.back(), step, reach, 0.5, offset ) )
        candidates.push_back( { p, vertices.size() } );
      for ( const Eigen::Vector3d &p : continuation( groundLine, lineDirection, reach, 0.5 ) )
        candidates.push_back( { p, vertices.size() } );
    }
    LocateOptions locate = locateOptionsFor( profile, options.follow.directional.follow, 8.0 );
    LocateOptions snap = locate;
    snap.searchHalfPx = 3.0;
    Eigen::Vector3d correction = Eigen::Vector3d::Zero();
    struct CorrelatedStart
    {
      Eigen::Vector2d pixel, direction;
      size_t keep;
    };
    std::optional<CorrelatedStart> correlatedStart;
    // first Xin's (1995) way: a vertex of this station, its surroundings in this image found in the next by
    // correlation - the two stations' poses may disagree by more than the distance to a parallel edge (the
    // edge line's paint beside the kerb). Vertices about 10 m ahead of the next camera, where a pose error
    // moves the image least and the window still shows the line's surroundings.
    {
      std::vector<std::pair<double, size_t>> byRange;
      for ( size_t i = firstOfStation; i < vertices.size(); ++i )
      {
        const double range = horizontalDistance( vertices[i].point, nextCentre );
        if ( range >= options.handoverRangeM && ( vertices[i].point - nextCentre ).dot( lineDirection ) > 0 )
          byRange.push_back( { std::abs( range - 10.0 ), i } );
      }
      std::sort( byRange.begin(), byRange.end() );
      // how far apart the two poses may put a point: three times their relative sigma
      const auto positionSigma = []( const OrientedImage &image )
      {
        const std::optional<ExteriorSigma> &sigma = image.exterior().sigma;
        return sigma ? std::max( { sigma->x, sigma->y, sigma->z } ) : 0.0;
      };
      const double relativeSigmaM = std::hypot( positionSigma( *in.reference ), positionSigma( next ) );
      for ( size_t c = 0; c < byRange.size() && c < static_cast<size_t>( options.handoverCorrelations ) && !correlatedStart; ++c )
      {
        const size_t i = byRange[c].second;
        const Eigen::Vector3d &point = vertices[i].point;
        const Eigen::Vector3d along = directionAt( point );
        const GroundProjection p = next.projectGroundToPixel( point ), ahead = next.projectGroundToPixel( point + along );
        const Eigen::Vector3d across = Eigen::Vector3d( -along.y(), along.x(), 0.0 ).normalized();
        const GroundProjection side = next.projectGroundToPixel( point + across );
        if ( !p.ok() || !ahead.ok() || !side.ok() || !p.inFrame )
          continue;
        const Eigen::Vector2d d = ( ahead.pixelInImage - p.pixelInImage ).normalized();
        // where the poses cannot disagree by more than the locating window, the line is simply located below
        const double disagreementPx = 3.0 * relativeSigmaM * ( side.pixelInImage - p.pixelInImage ).norm();
        if ( disagreementPx <= locate.searchHalfPx )
          break;
        HandoverOptions handover = options.handover;
        handover.searchAcrossPx = std::clamp( disagreementPx, options.handover.searchAcrossPx, options.handover.maxSearchAcrossPx );
        const HandoverMatch m = refineHandover( *in.referenceGrey, *in.reference, vertices[i].pixels.front(), *in.nextGrey, next, nextGround, d, handover );
        if ( !m.found )
          continue;
        LineProfile expected = profile;
        if ( expected.kind != LineKind::Edge && widthTimesRange > 0 )
          expected.widthPx = widthTimesRange / std::max( horizontalDistance( point, nextCentre ), 1.0 );
        if ( const std::optional<LineHit> hit = locateLine( *in.nextGrey, m.pixelInNext, d, expected, snap ) )
        {
          LocateOptions confirm = locate;
          confirm.searchHalfPx = 2.0;
          if ( locateLine( *in.nextGrey, hit->pixelInImage + 3.0 * d, d, expected, confirm ) )
            if ( const std::optional<Eigen::Vector3d> found = nextGround( next, hit->pixelInImage ) )
            {
              // the two poses' disagreement on the ground; the nearest point of the line is then taken over below
              correction = *found - point;
              correlatedStart = { hit->pixelInImage, d, i };
            }
        }
      }
    }
    for ( const auto &[uncorrected, kept] : candidates )
    {
      const Eigen::Vector3d point = uncorrected + correction;
      const double range = horizontalDistance( point, nextCentre );
      if ( range < options.handoverRangeM || ( point - nextCentre ).dot( lineDirection ) <= 0 )
        continue;
      const Eigen::Vector3d along = directionAt( point );
      const GroundProjection p = next.projectGroundToPixel( point ), ahead = next.projectGroundToPixel( point + along );
      if ( !p.ok() || !ahead.ok() || p.pixelInImage.x() < 12 || p.pixelInImage.y() < 12 || p.pixelInImage.x() > in.nextGrey->cols - 12 || p.pixelInImage.y() > in.nextGrey->rows - 12 )
        continue;
      const Eigen::Vector2d d = ( ahead.pixelInImage - p.pixelInImage ).normalized();
      LineProfile expected = profile;
      if ( expected.kind != LineKind::Edge && widthTimesRange > 0 )
        expected.widthPx = widthTimesRange / std::max( range, 1.0 );
      // a point of the continuation is only as good as the extrapolation: its lateral uncertainty grows with the
      // distance from the line's end (0.15 m + 2 %), searched across up to 20 px
      LocateOptions around = locate;
      if ( kept == vertices.size() )
      {
        const double lateralM = 0.15 + 0.02 * horizontalDistance( point, groundLine.back() );
        const Eigen::Vector3d across = Eigen::Vector3d( -along.y(), along.x(), 0.0 ).normalized();
        const GroundProjection side = next.projectGroundToPixel( point + lateralM * across );
        if ( side.ok() )
          around.searchHalfPx = std::clamp( ( side.pixelInImage - p.pixelInImage ).norm(), locate.searchHalfPx, 20.0 );
      }
      const std::optional<LineHit> hit = locateLine( *in.nextGrey, p.pixelInImage, d, expected, around );
      if ( !hit )
        continue;
      LocateOptions confirm = locate;
      confirm.searchHalfPx = 2.0;
      if ( !locateLine( *in.nextGrey, hit->pixelInImage + 3.0 * d, d, expected, confirm ) )
        continue;
      return DynamicLink { hit->pixelInImage, d, kept };
    }
    // no nearer point of the line confirmed: the correlated vertex itself
    if ( correlatedStart )
      return DynamicLink { correlatedStart->pixel, correlatedStart->direction, correlatedStart->keep };
    return std::nullopt;
  }

} // namespace geostation
