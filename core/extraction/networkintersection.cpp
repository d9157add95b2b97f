/***************************************************************************
  networkintersection.cpp - the extracted network in 3-D
 ***************************************************************************/
#include "extraction/networkintersection.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "adjustment/intersection.h"
#include "extraction/verification.h"
#include "matching/matchingwindows.h"

namespace geostation
{

  double NetworkLine::lengthM() const
  {
    double length = 0.0;
    for ( size_t k = 1; k < vertices.size(); ++k )
      length += ( vertices[k].point - vertices[k - 1].point ).norm();
    return length;
  }

  double NetworkLine::sigmaMaxM() const
  {
    double sigma = 0.0;
    for ( const NetworkVertex &v : vertices )
      sigma = std::max( sigma, v.sigmaM.maxCoeff() );
    return sigma;
  }


  namespace
  {
    //! A band is a short stretch of curve: its window stays far below this.
    constexpr long long kMaxBandWindowPixels = 4LL << 20;

    //! Where segments p0-p1 and q0-q1 cross: the point and the sine of their angle.
    std::optional<std::pair<Eigen::Vector2d, double>> crossing( const Eigen::Vector2d &p0, const Eigen::Vector2d &p1, const Eigen::Vector2d &q0, const Eigen::Vector2d &q1 )
    {
      const Eigen::Vector2d r = p1 - p0, s = q1 - q0;
      const double denom = r.x() * s.y() - r.y() * s.x();
      if ( std::abs( denom ) < 1e-12 )
        return std::nullopt;
      const Eigen::Vector2d d = q0 - p0;
      const double t = ( d.x() * s.y() - d.y() * s.x() ) / denom;
      const double u = ( d.x() * r.y() - d.y() * r.x() ) / denom;
      if ( t < 0 || t > 1 || u < 0 || u > 1 )
        return std::nullopt;
      return std::make_pair( Eigen::Vector2d( p0 + t * r ), std::abs( denom ) / ( r.norm() * s.norm() ) );
    }
  } // namespace

  NetworkIntersectionSummary intersectNetwork( const OrientedPairMapping &mapping, const std::vector<CompiledPolygon> &linesA,
                                               const std::vector<CompiledPolygon> &linesB, const MatchImage &imageA, const MatchImage &imageB,
                                               const NetworkIntersectionOptions &options )
  {
    PairMatchWindows images( imageA, imageB );
    return intersectNetwork( mapping, linesA, linesB, images, options );
  }

  NetworkIntersectionSummary intersectNetwork( const OrientedPairMapping &mapping, const std::vector<CompiledPolygon> &linesA,
                                               const std::vector<CompiledPolygon> &linesB, PairMatchWindows &images,
                                               const NetworkIntersectionOptions &options )
  {
    NetworkIntersectionSummary summary;
    const OrientedImage &a = mapping.imageA(), &b = mapping.imageB();
    const double minSine = std::sin( options.minCrossingAngleDeg * kPi / 180.0 );
    for ( size_t li = 0; li < linesA.size(); ++li )
    {
      NetworkLine current;
      current.sourceLine = static_cast<int>( li );
      int missing = 0;
      const auto flush = [&]
      {
        if ( current.vertices.size() >= 2 )
          summary.lines.push_back( current );
        current.vertices.clear();
      };
      for ( const Eigen::Vector2d &p : densifyPolyline( linesA[li].pixels, options.vertexSpacingPx ) )
      {
        ++summary.vertices;
        const std::optional<Eigen::Vector3d> ground = mapping.groundPoint( a, p );
        const std::optional<Ray> ray = a.worldRayFromPixel( p );
        Eigen::Vector2d inB = Eigen::Vector2d::Zero();
        bool haveB = false;
        double sigmaB = options.lineSigmaPx;
        std::string method;
        if ( ground && ray && std::abs( ray->direction.z() ) > 1e-6 )
        {
          // the epipolar curve for heights around the mapped one, as a polyline
          std::vector<Eigen::Vector2d> curve;
          for ( int k = -8; k <= 8; ++k )
          {
            const double z = ground->z() + options.heightRangeM * k / 8.0;
            const double t = ( z - ray->origin.z() ) / ray->direction.z();
            if ( t <= 0 )
              continue;
            const GroundProjection g = b.projectGroundToPixel( ray->origin + t * ray->direction );
            if ( g.ok() )
              curve.push_back( g.pixelInImage );
          }
          const GroundProjection predicted = b.projectGroundToPixel( *ground );
          if ( curve.size() >= 2 && predicted.ok() )
          {
            const Eigen::Vector2d pred = predicted.pixelInImage;
            double bestDistance = options.searchPx;
            double bestSine = 0.0;
            for ( const CompiledPolygon &line : linesB )
              for ( size_t i = 0; i + 1 < line.pixels.size(); ++i )
              {
                const Eigen::Vector2d &q0 = line.pixels[i], &q1 = line.pixels[i + 1];
                if ( ( ( q0 + q1 ) * 0.5 - pred ).norm() > options.searchPx + 0.5 * ( q1 - q0 ).norm() )
                  continue;
                for ( size_t k = 0; k + 1 < curve.size(); ++k )
                  if ( const auto c = crossing( curve[k], curve[k + 1], q0, q1 ) )
                    if ( ( c->first - pred ).norm() < bestDistance )
                    {
                      bestDistance = ( c->first - pred ).norm();
                      bestSine = c->second;
                      inB = c->first;
                      haveB = true;
                    }
              }
            if ( haveB && bestSine >= minSine )
            {
              sigmaB = options.lineSigmaPx / bestSine;
              method = "line_crossing";
            }
            else if ( images.available() )
            {
              // along the epipolar direction: area matching on the curve near the prediction
              haveB = false;
              std::vector<Eigen::Vector2d> band;
              for ( const Eigen::Vector2d &c : densifyPolyline( curve, 1.0 ) )
                if ( ( c - pred ).norm() <= options.searchPx )
                  band.push_back( c );
              if ( band.size() >= 3 )
              {
                // the pixels this match reads, in windows when the images are not held whole
                const MatchImage &imageA = images.holding( 0, matchingWindowAround( p, 0.0, options.areaMatch, images.size( 0 ) ) );
                const MatchImage &imageB = images.holding( 1, matchingWindowAlong( band, options.areaMatch, images.size( 1 ), kMaxBandWindowPixels ) );
                const AreaMatch m = matchAlongEpipolarBand( imageA, p, imageB, band, options.areaMatch );
                if ( m.status == MatchStatus::Lsm || m.status == MatchStatus::Correlation )
                {
                  inB = m.pixelInImage;
                  haveB = true;
                  sigmaB = std::max( m.sigmaPx, 0.3 );
                  method = "area_match";
                }
              }
            }
            else
              haveB = false;
          }
        }
        if ( !haveB )
        {
          ++summary.unmatched;
          if ( ++missing > options.maxGapVertices )
            flush();
          continue;
        }
        const std::vector<RayObservation> rays { { &a, p, options.lineSigmaPx }, { &b, inB, sigmaB } };
        const IntersectionSummary x = intersectRays( rays );
        if ( !x.ok() )
        {
          ++summary.unmatched;
          if ( ++missing > options.maxGapVertices )
            flush();
          continue;
        }
        missing = 0;
        NetworkVertex v;
        v.point = x.point;
        v.sigmaM = x.sigmaM;
        v.inA = p;
        v.inB = inB;
        v.method = method;
        ( method == "line_crossing" ? summary.byCrossing : summary.byArea )++;
        current.vertices.push_back( v );
      }
      flush();
    }
    return summary;
  }

} // namespace geostation
