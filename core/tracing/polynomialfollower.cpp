/***************************************************************************
  polynomialfollower.cpp - polynomial edge fitting (§6.3.3)
 ***************************************************************************/
#include "tracing/polynomialfollower.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <Eigen/Dense>

#include "tracing/lineprofile.h"

namespace geostation
{
  namespace
  {
    struct Candidate
    {
      double u, v, width;
    };

    struct StripFit
    {
      Eigen::Vector3d k = Eigen::Vector3d::Zero(); //!< k0, k1, k2 (k2 = 0 for a straight strip)
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      bool curved = false;
      double sigma0 = 0.0;
      std::vector<Candidate> inliers;

      double v( double u ) const { return k[0] + k[1] * u + k[2] * u * u; }
      double slope( double u ) const { return k[1] + 2 * k[2] * u; }
      double sigmaAt( double u ) const
      {
        const Eigen::Vector3d a( 1, u, u * u );
        return std::sqrt( std::max( 0.0, a.dot( covariance * a ) ) );
      }
    };

    //! Least squares v = k0 + k1 u (+ k2 u^2), eqs. 6.17-6.20.
    bool fit( const std::vector<Candidate> &c, bool quadratic, StripFit &out )
    {
      const int m = quadratic ? 3 : 2;
      if ( static_cast<int>( c.size() ) < m + 2 )
        return false;
      Eigen::MatrixXd a( c.size(), m );
      Eigen::VectorXd l( c.size() );
      for ( size_t i = 0; i < c.size(); ++i )
      {
        a( i, 0 ) = 1.0;
        a( i, 1 ) = c[i].u;
        if ( quadratic )
          a( i, 2 ) = c[i].u * c[i].u;
        l[i] = c[i].v;
      }
      const Eigen::MatrixXd n = a.transpose() * a;
      const Eigen::VectorXd x = n.ldlt().solve( a.transpose() * l );
      const double s0 = std::sqrt( ( a * x - l ).squaredNorm() / std::max( 1.0, static_cast<double>( c.size() - m ) ) );
      out.k.setZero();
      out.k.head( m ) = x;
      out.covariance.setZero();
      out.covariance.topLeftCorner( m, m ) = s0 * s0 * n.inverse();
      out.curved = quadratic;
      out.sigma0 = s0;
      out.inliers = c;
      return true;
    }
  }

  namespace
  {
    /**
     * Where a strip's inliers support the line: from the first to the last
     * run of at least 4 inliers no more than 3 px apart (an isolated hit on
     * noise or texture near the fitted curve, in a gap before or after a
     * dash, does not extend the line); all inliers when there is no such run.
     */
    std::pair<double, double> supportedSpan( const std::vector<Candidate> &inliers )
    {
      std::vector<double> u;
      for ( const Candidate &c : inliers )
        u.push_back( c.u );
      std::sort( u.begin(), u.end() );
      if ( u.empty() )
        return { 0.0, 0.0 };
      constexpr size_t kRun = 4;
      constexpr double kStepPx = 3.0;
      std::optional<double> first, last;
      for ( size_t i = 0, runStart = 0; i < u.size(); ++i )
      {
        if ( i > 0 && u[i] - u[i - 1] > kStepPx )
          runStart = i;
        if ( i + 1 - runStart >= kRun )
        {
          if ( !first )
            first = u[runStart];
          last = u[i];
        }
      }
      return first ? std::make_pair( *first, *last ) : std::make_pair( u.front(), u.back() );
    }
  }

  FollowResult followPolynomial( const cv::Mat &grey, const FollowRequest &request, const PolynomialFollowOptions &options )
  {
    FollowResult out;
    out.profile = request.profile;
    Eigen::Vector2d origin = request.start, direction = request.direction.normalized();
    double curvature = 0.0; // k2 carried into the next strip's prediction
    const double length = options.stripLengthPx;
    out.stop = TraceStop::EndOfLine;
    for ( int strip = 0; strip < request.maxSteps / std::max( 1, options.stripLengthPx ); ++strip )
    {
      const Eigen::Vector2d normal = rightNormal( direction );
      LocateOptions locate = locateOptionsFor( out.profile, options.follow, options.stripHalfWidthPx );
      std::vector<Candidate> candidates;
      double reach = length;
      bool limitReached = false, leftImage = false;
      for ( int u = 1; u <= length; ++u )
      {
        const Eigen::Vector2d q = origin + u * direction + curvature * u * u * normal;
        if ( !sampleGrey( grey, q ) )
        {
          reach = u - 1;
          leftImage = true;
          break;
        }
        if ( request.withinLimit && !request.withinLimit( q ) )
        {
          reach = u - 1;
          limitReached = true;
          break;
        }
        if ( const std::optional<LineHit> hit = locateLine( grey, q, direction, out.profile, locate ) )
        {
          const Eigen::Vector2d rel = hit->pixelInImage - origin;
          candidates.push_back( { rel.dot( direction ), rel.dot( normal ), hit->widthPx } );
        }
      }
      if ( reach < 4 || static_cast<double>( candidates.size() ) < std::max( 5.0, options.minSupport * reach ) )
      {
        out.stop = leftImage ? TraceStop::LeftImage : limitReached ? TraceStop::DistanceLimit : TraceStop::EndOfLine;
        break;
      }
      // first pass: quadratic; straight if it bends the strip by less than the tolerance
      StripFit f;
      if ( !fit( candidates, true, f ) )
        break;
      if ( std::abs( f.k[2] ) * 0.25 * reach * reach < options.straightTolerancePx )
        fit( candidates, false, f );
      // second pass without the candidates off the fitted line
      std::vector<Candidate> kept;
      const double threshold = std::max( options.outlierPx, 2.5 * f.sigma0 );
      for ( const Candidate &c : candidates )
        if ( std::abs( c.v - f.v( c.u ) ) <= threshold )
          kept.push_back( c );
      if ( static_cast<double>( kept.size() ) < std::max( 5.0, options.minSupport * reach ) || !fit( kept, f.curved, f ) )
        break;
      std::vector<double> widths;
      for ( const Candidate &c : f.inliers )
        widths.push_back( c.width );
      const auto [uStart, uEnd] = supportedSpan( f.inliers );
      if ( out.profile.kind != LineKind::Edge && !widths.empty() )
      {
        std::nth_element( widths.begin(), widths.begin() + widths.size() / 2, widths.end() );
        out.profile.widthPx = 0.5 * out.profile.widthPx + 0.5 * widths[widths.size() / 2];
      }
      const auto pointAt = [&]( double u ) { return Eigen::Vector2d( origin + u * direction + f.v( u ) * normal ); };
      const int interval = f.curved ? options.intervalCurvedPx : options.intervalStraightPx;
      // the fit's sigma assumes independent candidates; worn paint and texture shift neighbouring
      // cross-sections together, so a point is no better than a few of them (measured: 0.45 sigma0)
      const auto pointSigma = [&]( double u ) { return std::max( { 0.05, f.sigmaAt( u ), options.correlatedFraction * f.sigma0 } ); };
      // the first strip starts where its support does: a start in a gap (a dash ahead, a worn patch) is
      // not on the line, and the polynomial is not extrapolated back to it
      const double uFirst = strip == 0 && uStart > 0.5 * interval ? uStart : 0.0;
      if ( strip == 0 )
      {
        out.points.push_back( pointAt( uFirst ) );
        out.sigmaPx.push_back( pointSigma( uFirst ) );
      }
      for ( double u = uFirst + interval; u < uEnd - 0.5 * interval; u += interval )
      {
        out.points.push_back( pointAt( u ) );
        out.sigmaPx.push_back( pointSigma( u ) );
      }
      out.points.push_back( pointAt( uEnd ) );
      out.sigmaPx.push_back( pointSigma( uEnd ) );
      out.pixelsFollowed += static_cast<int>( uEnd - uFirst );
      // the next strip along the fitted tangent at the last supported point
      const Eigen::Vector2d tangent = ( direction + f.slope( uEnd ) * normal ).normalized();
      if ( std::acos( std::clamp( tangent.dot( direction ), -1.0, 1.0 ) ) * 180.0 / kPi > options.follow.maxDirectionChangeDeg )
      {
        out.stop = TraceStop::DirectionChange;
        break;
      }
      origin = pointAt( uEnd );
      direction = tangent;
      curvature = f.k[2];
      if ( limitReached || leftImage )
      {
        out.stop = limitReached ? TraceStop::DistanceLimit : TraceStop::LeftImage;
        break;
      }
      if ( uEnd < reach - std::max( 10.0, 0.25 * reach ) )
        break; // support ends inside the strip: end of a dash, a gap, or the end of the line
      if ( uEnd < 2.0 )
        break;
    }
    out.direction = direction;
    return out;
  }

} // namespace geostation
