/***************************************************************************
  multiimagematcher.cpp - master pair candidates confirmed in other images
 ***************************************************************************/
#include "matching/multiimagematcher.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

namespace geostation
{
  namespace
  {
    //! Sobel magnitude at a pixel of the grey image (0 at the border).
    double edgeStrength( const MatchImage &image, const Eigen::Vector2d &pixel )
    {
      const int c = static_cast<int>( std::floor( pixel.x() ) ), r = static_cast<int>( std::floor( pixel.y() ) );
      if ( c < 1 || r < 1 || c + 1 >= image.width() || r + 1 >= image.height() || !image.holds( cv::Rect( c - 1, r - 1, 3, 3 ) ) )
        return 0.0;
      const auto g = [&]( int dr, int dc ) { return static_cast<double>( *image.greyAt( c + dc, r + dr ) ); };
      const double gx = ( g( -1, 1 ) + 2 * g( 0, 1 ) + g( 1, 1 ) ) - ( g( -1, -1 ) + 2 * g( 0, -1 ) + g( 1, -1 ) );
      const double gy = ( g( 1, -1 ) + 2 * g( 1, 0 ) + g( 1, 1 ) ) - ( g( -1, -1 ) + 2 * g( -1, 0 ) + g( -1, 1 ) );
      return std::hypot( gx, gy );
    }
  }

  std::optional<Eigen::Vector3d> nearestPointToRays( const std::vector<Ray> &rays )
  {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for ( const Ray &ray : rays )
    {
      const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - ray.direction * ray.direction.transpose();
      a += p;
      b += p * ray.origin;
    }
    const Eigen::FullPivLU<Eigen::Matrix3d> lu( a );
    if ( rays.size() < 2 || lu.rank() < 3 )
      return std::nullopt;
    return lu.solve( b );
  }

  MultiImageMatch matchMultiImage( const std::vector<MatchView> &views, size_t reference, size_t master, const Eigen::Vector2d &pixelInReference,
                                   const MultiImageMatchOptions &options )
  {
    MultiImageMatch result;
    result.pixels.assign( views.size(), std::nullopt );
    result.scores.assign( views.size(), 0.0 );
    if ( reference >= views.size() || master >= views.size() || reference == master )
      throw std::invalid_argument( "the reference and master images must be two different views" );
    const MatchView &ref = views[reference];
    const std::optional<Ray> referenceRay = ref.image->worldRayFromPixel( pixelInReference );
    if ( !referenceRay )
    {
      result.status = MatchStatus::Outside;
      result.message = "the reference pixel has no ray (outside the lens field)";
      return result;
    }
    const bool onEdge = options.edgeConstraint && edgeStrength( *ref.pixels, pixelInReference ) > options.edgeGradient;

    // 1. the master pair
    std::vector<Eigen::Vector2d> curve;
    for ( const auto &piece : epipolarCurve( *ref.image, pixelInReference, *views[master].image, options.epipolar ).pieces )
      for ( const EpipolarVertex &v : piece )
        curve.push_back( v.pixelInImage );
    AreaMatchOptions correlation = options.area;
    correlation.lsm = false;
    const AreaMatch pair = matchAlongEpipolarBand( *ref.pixels, pixelInReference, *views[master].pixels, curve, correlation );
    if ( pair.peaks.empty() )
    {
      result.status = pair.status;
      result.message = "master pair: " + pair.message;
      return result;
    }
    // Xin's (1995) procedure as it stands: a candidate is refined from its peak and confirmed by the correlation
    // threshold and the other images' geometry - that confirmation is the check here (matching back, made to
    // catch wrong pairs, rejects right refinements on repetitive stripes and lets a wrong candidate win)
    AreaMatchOptions confirm = options.area;
    confirm.lsmBelowThreshold = false;
    confirm.lsmStarts = 1;
    confirm.fallbackScales.clear();
    confirm.backMatch = false;
    confirm.borderIsNoPeak = false; // areas of 1.5-2 px around a peak or a projection: a refinement, not a search
    double bestTotal = -1.0;
    for ( const auto &[peak, peakScore] : pair.peaks )
    {
      if ( result.candidatesTried >= options.candidates || peakScore < options.area.minScore )
        break;
      ++result.candidatesTried;
      // refine the master match around the peak
      const AreaMatch masterMatch = matchAroundPosition( *ref.pixels, pixelInReference, *views[master].pixels, peak, 1.5, confirm );
      if ( !masterMatch.matched() )
        continue;
      if ( onEdge && edgeStrength( *views[master].pixels, masterMatch.pixelInImage ) < 0.5 * options.edgeGradient )
        continue;
      // 2. intersect
      const std::optional<Ray> masterRay = views[master].image->worldRayFromPixel( masterMatch.pixelInImage );
      if ( !masterRay )
        continue;
      std::vector<Ray> rays { *referenceRay, *masterRay };
      const std::optional<Eigen::Vector3d> point = nearestPointToRays( rays );
      if ( !point )
        continue;
      const double depth = ( *point - referenceRay->origin ).dot( referenceRay->direction );
      if ( depth < options.epipolar.minDistanceM || depth > options.epipolar.maxDistanceM )
        continue; // triangulates outside the depth range (or behind)
      // 3.-5. confirm in the other images
      std::vector<std::optional<Eigen::Vector2d>> pixels( views.size() );
      std::vector<double> scores( views.size(), 0.0 );
      pixels[reference] = pixelInReference;
      scores[reference] = 1.0;
      pixels[master] = masterMatch.pixelInImage;
      scores[master] = masterMatch.score;
      double total = masterMatch.score;
      bool confirmed = true;
      for ( size_t v = 0; v < views.size() && confirmed; ++v )
      {
        if ( v == reference || v == master )
          continue;
        const GroundProjection projected = views[v].image->projectGroundToPixel( *point );
        if ( !projected.ok() || !projected.inFrame )
          continue; // the point is not in this image: it neither confirms nor refutes
        const AreaMatch other = matchAroundPosition( *ref.pixels, pixelInReference, *views[v].pixels, projected.pixelInImage, options.confirmRadiusPx, confirm );
        if ( !other.matched() || ( onEdge && edgeStrength( *views[v].pixels, other.pixelInImage ) < 0.5 * options.edgeGradient ) )
        {
          confirmed = false;
          break;
        }
        pixels[v] = other.pixelInImage;
        scores[v] = other.score;
        total += other.score;
        if ( const std::optional<Ray> ray = views[v].image->worldRayFromPixel( other.pixelInImage ) )
          rays.push_back( *ray );
      }
      if ( !confirmed || total <= bestTotal )
        continue;
      // 6. re-intersect from every ray
      const std::optional<Eigen::Vector3d> final = nearestPointToRays( rays );
      if ( !final )
        continue;
      bestTotal = total;
      result.status = masterMatch.status;
      result.world = *final;
      result.pixels = pixels;
      result.scores = scores;
    }
    if ( !result.matched() )
    {
      result.status = MatchStatus::Inconsistent;
      result.message = "no candidate of the master pair is confirmed by the other images";
    }
    return result;
  }

} // namespace geostation
