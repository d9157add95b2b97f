/***************************************************************************
  stationstereo.cpp - one station's reference line found in the partner, in 3-D
 ***************************************************************************/
#include "tracing/stationstereo.h"

#include <algorithm>

#include "tracing/linerelocation.h"
#include "tracing/roadtracer.h"

namespace geostation
{

  StationStereo traceStationStereo( const StationStereoInput &in, const RoadTraceOptions &options )
  {
    StationStereo out;
    const StereoImage &ref = in.reference, &par = in.partner;
    const OrientedImage &reference = *ref.image, &partner = *par.image;
    const cv::Mat &partnerGrey = *par.grey;
    const GroundOfPixel &ground = in.ground;
    const LineProfile &profile = in.profile;

    // the first points of the line that the partner sees, tried in turn
    std::vector<Eigen::Vector2d> points;
    std::vector<double> sigmas;
    intervalPoints( in.referenceLine, options.vertexSpacingPx, points, sigmas );
    LineRelocation relocation = options.relocation;
    relocation.profile = profile;
    relocation.widthTimesRange = in.widthTimesRange;
    if ( options.relocate )
      recentreOnLine( ref, points, sigmas, ground, relocation );
    out.partnerStart.message = "the line is not in view of " + par.imageId;
    for ( size_t i = 0, tries = 0; i < points.size() && tries < 6; ++i )
    {
      const std::optional<Eigen::Vector3d> g = ground( reference, points[i] );
      const GroundProjection p = g ? partner.projectGroundToPixel( *g ) : GroundProjection();
      if ( !g || !p.ok() || p.pixelInImage.x() < 15 || p.pixelInImage.y() < 15 || p.pixelInImage.x() > partnerGrey.cols - 15 || p.pixelInImage.y() > partnerGrey.rows - 15 )
        continue;
      ++tries;
      const Eigen::Vector2d along = ( points[std::min( i + 1, points.size() - 1 )] - points[i == 0 ? 0 : i - 1] ).normalized();
      out.partnerStart = matchStartInPartner( ref, points[i], along, par, ground, in.referenceLine.profile, options.start );
      if ( out.partnerStart.ok() )
        break;
    }
    if ( !out.partnerStart.ok() )
      return out;

    // the partner: the same method from the start found there, both ways so it covers all of the reference line
    FollowRequest partnerRequest = in.request;
    partnerRequest.start = out.partnerStart.pixelInImage;
    partnerRequest.direction = out.partnerStart.direction;
    partnerRequest.withinLimit = in.partnerWithinLimit;
    LineFollowOptions partnerFollow = in.follow;
    partnerFollow.groundDistanceM = [&]( const Eigen::Vector2d &a, const Eigen::Vector2d &b ) -> std::optional<double>
    {
      const std::optional<Eigen::Vector3d> ga = ground( partner, a ), gb = ground( partner, b );
      return ga && gb ? std::optional<double>( ( *ga - *gb ).norm() ) : std::nullopt;
    };
    if ( const std::optional<LineHit> snapped = locateLine( partnerGrey, partnerRequest.start, partnerRequest.direction, profile, locateOptionsFor( profile, options.follow.directional.follow, 4.0 ) ) )
      partnerRequest.start = snapped->pixelInImage;
    out.partnerLine = followLineBothWays( partnerGrey, partnerRequest, in.method, partnerFollow );

    VertexMatchOptions vertexOptions = options.vertices;
    if ( profile.kind != LineKind::Edge )
    {
      // a painted stripe's centre: good to so much on the road when relocated over a length of line, else in pixels
      if ( options.relocate )
        vertexOptions.lineSigmaM = std::max( vertexOptions.lineSigmaM, options.stripeSigmaM );
      else
        vertexOptions.pixelSigmaFloorPx = std::max( vertexOptions.pixelSigmaFloorPx, options.stripeSigmaFloorPx );
    }
    out.vertices = intersectLineVertices( ref, points, sigmas, par, out.partnerLine.line, ground, vertexOptions, options.relocate ? &relocation : nullptr );
    MultiStationOptions multi = options.multiStation;
    multi.sigmaFloorPx = std::max( multi.sigmaFloorPx, vertexOptions.pixelSigmaFloorPx );
    multi.lineSigmaM = std::max( multi.lineSigmaM, vertexOptions.lineSigmaM );
    const StationView own { in.stationId, { ref, par } };
    if ( options.locateInPartner && out.vertices.size() < points.size() )
    {
      // where the partner's line does not reach: the line located across the prediction in the partner
      std::vector<Eigen::Vector2d> missing;
      std::vector<double> missingSigmas;
      for ( size_t i = 0; i < points.size(); ++i )
        if ( std::none_of( out.vertices.begin(), out.vertices.end(), [&]( const LineVertex3d &v ) { return v.pixelInReference == points[i]; } ) )
        {
          missing.push_back( points[i] );
          missingSigmas.push_back( sigmas[i] );
        }
      const std::vector<LineVertex3d> located = verticesByLocatingInPartner( missing, missingSigmas, own, ground, profile, in.widthTimesRange, vertexOptions.heightToleranceM, multi );
      out.vertices.insert( out.vertices.end(), located.begin(), located.end() );
      // back into the reference line's order
      std::stable_sort( out.vertices.begin(), out.vertices.end(), [&]( const LineVertex3d &a, const LineVertex3d &b ) {
        return std::find( points.begin(), points.end(), a.pixelInReference ) < std::find( points.begin(), points.end(), b.pixelInReference ); } );
    }
    // the stations before saw the line there too, with pose errors of their own
    if ( !in.behind.empty() )
      out.multiStation = refineFromOtherStations( out.vertices, own, in.behind, profile, in.widthTimesRange, in.lineDirection, multi );
    return out;
  }

} // namespace geostation
