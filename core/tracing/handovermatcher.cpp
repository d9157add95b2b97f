/***************************************************************************
  handovermatcher.cpp
 ***************************************************************************/
#include "tracing/handovermatcher.h"

#include <cmath>

#include "tracing/linetrace.h"

namespace geostation
{

  namespace
  {
    //! Normalised cross-correlation of the template with the next image at the template's positions shifted by `shift`.
    double correlation( const std::vector<double> &values, const std::vector<Eigen::Vector2d> &positions, const cv::Mat &grey, const Eigen::Vector2d &shift )
    {
      double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
      int n = 0;
      for ( size_t i = 0; i < values.size(); ++i )
      {
        const std::optional<double> b = sampleGrey( grey, positions[i] + shift );
        if ( !b )
          return -1.0;
        const double a = values[i];
        sa += a;
        sb += *b;
        saa += a * a;
        sbb += *b * *b;
        sab += a * *b;
        ++n;
      }
      const double va = saa - sa * sa / n, vb = sbb - sb * sb / n;
      return va > 0 && vb > 0 ? ( sab - sa * sb / n ) / std::sqrt( va * vb ) : -1.0;
    }
  }

  HandoverMatch refineHandover( const cv::Mat &previousGrey, const OrientedImage &previous, const Eigen::Vector2d &pixelInPrevious, const cv::Mat &nextGrey,
                                const OrientedImage &next, const GroundOfPixel &surface, const Eigen::Vector2d &directionInNext,
                                const HandoverOptions &options )
  {
    HandoverMatch out;
    // where the two poses put the point in the next image: its ray from the previous camera meets the surface there
    const std::optional<Eigen::Vector3d> onSurface = surface( previous, pixelInPrevious );
    const GroundProjection predicted = onSurface ? next.projectGroundToPixel( *onSurface ) : GroundProjection();
    if ( !predicted.ok() )
      return out;
    const Eigen::Vector2d predictedInNext = predicted.pixelInImage;
    const Eigen::Vector2d along = directionInNext.normalized(), across = rightNormal( along );
    // the previous image resampled into the next image's geometry around the prediction
    std::vector<double> values;
    std::vector<Eigen::Vector2d> positions;
    for ( int v = -options.halfAlongPx; v <= options.halfAlongPx; ++v )
      for ( int u = -options.halfAcrossPx; u <= options.halfAcrossPx; ++u )
      {
        const Eigen::Vector2d q = predictedInNext + u * across + v * along;
        const std::optional<Eigen::Vector3d> ground = surface( next, q );
        if ( !ground )
          return out;
        const GroundProjection p = previous.projectGroundToPixel( *ground );
        const std::optional<double> g = p.ok() ? sampleGrey( previousGrey, p.pixelInImage ) : std::nullopt;
        if ( !g )
          return out;
        values.push_back( *g );
        positions.push_back( q );
      }
    double mean = 0, sq = 0;
    for ( const double g : values )
    {
      mean += g;
      sq += g * g;
    }
    mean /= values.size();
    if ( std::sqrt( std::max( 0.0, sq / values.size() - mean * mean ) ) < options.minContrast )
      return out;
    // whole-pixel search across and along, then a parabola through the best across
    double best = -2.0;
    Eigen::Vector2d bestShift = Eigen::Vector2d::Zero();
    for ( double s = -options.searchAlongPx; s <= options.searchAlongPx; s += 1.0 )
      for ( double t = -options.searchAcrossPx; t <= options.searchAcrossPx; t += 1.0 )
      {
        const Eigen::Vector2d shift = t * across + s * along;
        const double c = correlation( values, positions, nextGrey, shift );
        if ( c > best )
        {
          best = c;
          bestShift = Eigen::Vector2d( t, s );
        }
      }
    if ( best < options.minScore )
    {
      out.score = best;
      return out;
    }
    const auto at = [&]( double t ) { return correlation( values, positions, nextGrey, t * across + bestShift.y() * along ); };
    const double cm = at( bestShift.x() - 1.0 ), cp = at( bestShift.x() + 1.0 ), denom = cm - 2.0 * best + cp;
    const double subpixel = denom < 0 ? std::clamp( 0.5 * ( cm - cp ) / denom, -0.5, 0.5 ) : 0.0;
    out.found = true;
    out.score = best;
    out.shiftPx = Eigen::Vector2d( bestShift.x() + subpixel, bestShift.y() );
    out.pixelInNext = predictedInNext + out.shiftPx.x() * across + out.shiftPx.y() * along;
    return out;
  }

} // namespace geostation
