// The buffer method for lines in an image (pixelInImage polylines):
//   completeness = truth length within the buffer of the result,
//   correctness  = result length within the buffer of the truth,
// both sampled every pixel along the lines; and the RMS distance of the
// result to the truth where the result lies within the buffer.
#ifndef GEOSTATION_TESTS_IMAGELINESCORING_H
#define GEOSTATION_TESTS_IMAGELINESCORING_H

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

namespace geostation
{
  using PixelPolyline = std::vector<Eigen::Vector2d>;

  inline double distanceToSegment( const Eigen::Vector2d &p, const Eigen::Vector2d &a, const Eigen::Vector2d &b )
  {
    const Eigen::Vector2d d = b - a;
    const double t = d.squaredNorm() > 0 ? std::clamp( ( p - a ).dot( d ) / d.squaredNorm(), 0.0, 1.0 ) : 0.0;
    return ( a + t * d - p ).norm();
  }

  inline double distanceToLines( const Eigen::Vector2d &p, const std::vector<PixelPolyline> &lines )
  {
    double best = std::numeric_limits<double>::infinity();
    for ( const PixelPolyline &l : lines )
    {
      if ( l.size() == 1 )
        best = std::min( best, ( p - l.front() ).norm() );
      for ( size_t i = 0; i + 1 < l.size(); ++i )
        best = std::min( best, distanceToSegment( p, l[i], l[i + 1] ) );
    }
    return best;
  }

  //! Calls f( point, length ) at steps of at most 1 px along the lines.
  template <typename F> void alongLines( const std::vector<PixelPolyline> &lines, F f )
  {
    for ( const PixelPolyline &l : lines )
      for ( size_t i = 0; i + 1 < l.size(); ++i )
      {
        const double length = ( l[i + 1] - l[i] ).norm();
        const int n = std::max( 1, static_cast<int>( std::ceil( length ) ) );
        for ( int k = 0; k < n; ++k )
          f( Eigen::Vector2d( l[i] + ( k + 0.5 ) / n * ( l[i + 1] - l[i] ) ), length / n );
      }
  }

  //! The lines' length inside the polygons `areas` (areas where no road is, say).
  inline double lengthInAreas( const std::vector<PixelPolyline> &lines, const std::vector<std::vector<cv::Point2f>> &areas )
  {
    double inside = 0.0;
    alongLines( lines, [&]( const Eigen::Vector2d &p, double length ) {
      for ( const std::vector<cv::Point2f> &area : areas )
        if ( cv::pointPolygonTest( area, cv::Point2f( static_cast<float>( p.x() ), static_cast<float>( p.y() ) ), false ) >= 0 )
          inside += length;
    } );
    return inside;
  }

  //! A road of a hand-digitised truth: its centre line and half width.
  struct TruthRoad
  {
    std::string name;
    double halfWidthPx = 0.0;
    PixelPolyline centre;
  };

  inline double totalLength( const std::vector<PixelPolyline> &lines )
  {
    double total = 0.0;
    alongLines( lines, [&]( const Eigen::Vector2d &, double length ) { total += length; } );
    return total;
  }

  //! The length of `roads` within their half width + `tolerancePx` of `lines`, and their whole length.
  inline std::pair<double, double> lengthFound( const std::vector<TruthRoad> &roads, const std::vector<PixelPolyline> &lines, double tolerancePx )
  {
    double total = 0.0, found = 0.0;
    for ( const TruthRoad &road : roads )
      alongLines( { road.centre }, [&]( const Eigen::Vector2d &p, double length ) {
        total += length;
        if ( distanceToLines( p, lines ) <= road.halfWidthPx + tolerancePx )
          found += length;
      } );
    return { found, total };
  }

  struct ImageBufferScore
  {
    double completeness = 0.0;
    double correctness = 0.0;
    double rmsPx = 0.0;   //!< of the result within the buffer, to the truth
    double worstPx = 0.0; //!< largest distance of the result to the truth
  };

  inline ImageBufferScore imageBufferScore( const std::vector<PixelPolyline> &result, const std::vector<PixelPolyline> &truth, double bufferPx )
  {
    ImageBufferScore s;
    double truthTotal = 0.0, truthWithin = 0.0, resultTotal = 0.0, resultWithin = 0.0, sum2 = 0.0;
    alongLines( truth, [&]( const Eigen::Vector2d &p, double length ) {
      truthTotal += length;
      if ( distanceToLines( p, result ) <= bufferPx )
        truthWithin += length;
    } );
    alongLines( result, [&]( const Eigen::Vector2d &p, double length ) {
      resultTotal += length;
      const double d = distanceToLines( p, truth );
      s.worstPx = std::max( s.worstPx, d );
      if ( d <= bufferPx )
      {
        resultWithin += length;
        sum2 += d * d * length;
      }
    } );
    s.completeness = truthTotal > 0 ? truthWithin / truthTotal : 0.0;
    s.correctness = resultTotal > 0 ? resultWithin / resultTotal : 0.0;
    s.rmsPx = resultWithin > 0 ? std::sqrt( sum2 / resultWithin ) : 0.0;
    return s;
  }
} // namespace geostation

#endif // GEOSTATION_TESTS_IMAGELINESCORING_H
