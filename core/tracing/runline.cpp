/***************************************************************************
  runline.cpp - one station's vertices into the run's traced line
 ***************************************************************************/
#include "tracing/runline.h"

#include <algorithm>
#include <cmath>

#include "tracing/heightcontinuity.h"

namespace geostation
{
  namespace
  {
    //! Drops the vertices from `first` on whose height leaves the line through their neighbours'; how many went.
    int dropHeightOutliers( std::vector<TracedVertex> &vertices, size_t first, const HeightContinuityOptions &options )
    {
      std::vector<Eigen::Vector3d> points;
      std::vector<double> sigmaZ;
      for ( const TracedVertex &v : vertices )
      {
        points.push_back( v.point );
        sigmaZ.push_back( std::sqrt( std::max( 0.0, v.covariance( 2, 2 ) ) ) );
      }
      const std::vector<size_t> outliers = heightOutliers( points, sigmaZ, first, options );
      for ( auto it = outliers.rbegin(); it != outliers.rend(); ++it )
        vertices.erase( vertices.begin() + static_cast<std::ptrdiff_t>( *it ) );
      return static_cast<int>( outliers.size() );
    }
  }

  StationPartSummary appendStationPart( std::vector<TracedVertex> &line, const std::vector<LineVertex3d> &vertices, const StationPart &part, const RoadTraceOptions &options )
  {
    const std::vector<TracedVertex> givingWay( line.begin() + static_cast<std::ptrdiff_t>( std::min( part.keep, line.size() ) ), line.end() );
    line.resize( std::min( part.keep, line.size() ) );
    const size_t firstOfStation = line.size();
    const Eigen::Vector3d &runAlong = part.runAlong;
    std::vector<const LineVertex3d *> ordered;
    for ( const LineVertex3d &v : vertices )
    {
      // a road line lies on the road: a vertex far off the surface is a wrong conjugate
      if ( part.surfaceHeight )
        if ( const std::optional<double> surface = part.surfaceHeight( v.point ); surface && std::abs( v.point.z() - *surface ) > options.surfaceToleranceM )
          continue;
      if ( !line.empty() && ( v.point - line.back().point ).head<2>().dot( runAlong.head<2>() ) <= 0 )
        continue;
      ordered.push_back( &v );
    }
    std::stable_sort( ordered.begin(), ordered.end(), [&]( const LineVertex3d *a, const LineVertex3d *b ) { return a->point.head<2>().dot( runAlong.head<2>() ) < b->point.head<2>().dot( runAlong.head<2>() ); } );
    // the previous station's vertices beyond the handover give way only where this station has vertices of its own
    // (within giveWayM along the run): where this station's line stopped short, they fill its gap
    std::vector<const TracedVertex *> kept;
    for ( const TracedVertex &g : givingWay )
    {
      const double at = g.point.head<2>().dot( runAlong.head<2>().normalized() );
      const bool covered = std::any_of( ordered.begin(), ordered.end(), [&]( const LineVertex3d *v ) {
        return std::abs( v->point.head<2>().dot( runAlong.head<2>().normalized() ) - at ) < options.giveWayM; } );
      if ( !covered )
        kept.push_back( &g );
    }
    for ( const LineVertex3d *v : ordered )
    {
      TracedVertex t;
      t.point = v->point;
      t.sigmaM = v->sigmaM;
      t.covariance = v->covariance;
      t.stationId = part.stationId;
      t.imageIds = { part.referenceImageId, part.partnerImageId };
      t.pixels = { v->pixelInReference, v->pixelInPartner };
      t.residualsPx = { v->residualReferencePx, v->residualPartnerPx };
      for ( const LineVertex3d::OtherObservation &o : v->others )
      {
        t.imageIds.push_back( o.imageId );
        t.pixels.push_back( o.pixelInImage );
        t.residualsPx.push_back( o.residualPx );
      }
      t.rangeM = v->rangeM;
      line.push_back( t );
    }
    if ( !kept.empty() )
    {
      for ( const TracedVertex *g : kept )
        line.push_back( *g );
      std::stable_sort( line.begin() + static_cast<std::ptrdiff_t>( firstOfStation ), line.end(), [&]( const TracedVertex &a, const TracedVertex &b ) {
        return a.point.head<2>().dot( runAlong.head<2>() ) < b.point.head<2>().dot( runAlong.head<2>() ); } );
    }
    const size_t ownVertices = line.size() - firstOfStation - kept.size();
    StationPartSummary out;
    out.firstOfStation = firstOfStation;
    out.heightOutliers = dropHeightOutliers( line, firstOfStation, options.heightContinuity );
    out.ownVertices = std::max( 0, static_cast<int>( ownVertices ) - out.heightOutliers );
    return out;
  }

} // namespace geostation
