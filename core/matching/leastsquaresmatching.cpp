/***************************************************************************
  leastsquaresmatching.cpp - affine + radiometric least-squares matching
 ***************************************************************************/
#include "matching/leastsquaresmatching.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace geostation
{

  namespace
  {
    using Parameters = Eigen::Matrix<double, 8, 1>; //!< a0 a1 a2 b0 b1 b2 h0 h1
    using Normal = Eigen::Matrix<double, 8, 8>;

    //! The target window: reference grey values and their pixels' offsets (px) from the reference point.
    struct TargetWindow
    {
      std::vector<double> values, dx, dy;
      int size() const { return static_cast<int>( values.size() ); }
    };

    /**
     * The reference pixels themselves (no resampling, which would smooth
     * them), centred on the pixel holding the reference point, optionally
     * smoothed by a Gaussian clipped at the image border. False if the window
     * leaves the reference image.
     */
    bool readTarget( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const LsmOptions &options, TargetWindow &window )
    {
      const int hw = options.windowWidth / 2, hh = options.windowHeight / 2;
      const int centreCol = static_cast<int>( std::floor( pixelInReference.x() ) ), centreRow = static_cast<int>( std::floor( pixelInReference.y() ) );
      if ( centreCol - hw < 0 || centreRow - hh < 0 || centreCol + hw >= reference.width() || centreRow + hh >= reference.height() )
        return false;
      const int blurRadius = options.referenceBlurPx > 0.0 ? static_cast<int>( std::ceil( 3.0 * options.referenceBlurPx ) ) : 0;
      // the pixels read, the blur's reach included (clipped at the image's border, as the blur is)
      const cv::Rect read = cv::Rect( centreCol - hw - blurRadius, centreRow - hh - blurRadius, 2 * ( hw + blurRadius ) + 1, 2 * ( hh + blurRadius ) + 1 )
                            & cv::Rect( 0, 0, reference.width(), reference.height() );
      if ( !reference.holds( read ) )
        return false;
      std::vector<double> kernel( 2 * blurRadius + 1, 1.0 );
      for ( int i = -blurRadius; i <= blurRadius && blurRadius > 0; ++i )
        kernel[i + blurRadius] = std::exp( -0.5 * i * i / ( options.referenceBlurPx * options.referenceBlurPx ) );
      const auto referenceValue = [&]( int row, int col ) -> double
      {
        if ( blurRadius == 0 )
          return reference.valueAt( col, row );
        double sum = 0.0, weights = 0.0;
        for ( int i = -blurRadius; i <= blurRadius; ++i )
          for ( int j = -blurRadius; j <= blurRadius; ++j )
            if ( row + i >= 0 && col + j >= 0 && row + i < reference.height() && col + j < reference.width() )
            {
              const double w = kernel[i + blurRadius] * kernel[j + blurRadius];
              sum += w * reference.valueAt( col + j, row + i );
              weights += w;
            }
        return sum / weights;
      };
      const int n = options.windowWidth * options.windowHeight;
      window.values.resize( n );
      window.dx.resize( n );
      window.dy.resize( n );
      for ( int r = -hh, k = 0; r <= hh; ++r )
        for ( int c = -hw; c <= hw; ++c, ++k )
        {
          window.values[k] = referenceValue( centreRow + r, centreCol + c );
          window.dx[k] = centreCol + c + 0.5 - pixelInReference.x();
          window.dy[k] = centreRow + r + 0.5 - pixelInReference.y();
        }
      return true;
    }

    //! The search image's squared gradients summed over the window mapped by p (grey levels^2 per px^2).
    double gradientEnergy( const MatchImage &search, const TargetWindow &window, const Parameters &p, bool bilinear )
    {
      double energy = 0.0;
      for ( int k = 0; k < window.size(); ++k )
      {
        const double col = p[0] + p[1] * window.dx[k] + p[2] * window.dy[k], row = p[3] + p[4] * window.dx[k] + p[5] * window.dy[k];
        if ( !search.canSampleCubic( col, row ) )
          continue;
        float dCol = 0, dRow = 0;
        if ( bilinear )
          search.sampleBilinear( col, row, &dCol, &dRow );
        else
          search.sampleCubic( col, row, &dCol, &dRow );
        energy += static_cast<double>( dCol ) * dCol + static_cast<double>( dRow ) * dRow;
      }
      return energy;
    }

    /**
     * The normal equations of the linearised observation equations (eq. 5.10)
     * at p: the lower triangle of `normal`, `rhs` and the residuals' sum of
     * squares. False if the window leaves the search image.
     */
    bool accumulate( const MatchImage &search, const TargetWindow &window, const Parameters &p, bool bilinear, Normal &normal, Parameters &rhs, double &sumSq )
    {
      normal.setZero();
      rhs.setZero();
      sumSq = 0.0;
      for ( int k = 0; k < window.size(); ++k )
      {
        const double col = p[0] + p[1] * window.dx[k] + p[2] * window.dy[k], row = p[3] + p[4] * window.dx[k] + p[5] * window.dy[k];
        if ( !search.canSampleCubic( col, row ) )
          return false;
        float dCol = 0, dRow = 0;
        const double g = bilinear ? search.sampleBilinear( col, row, &dCol, &dRow ) : search.sampleCubic( col, row, &dCol, &dRow );
        const double gx = p[7] * dCol, gy = p[7] * dRow;
        const double residual = window.values[k] - ( p[6] + p[7] * g );
        Parameters a;
        a << gx, gx * window.dx[k], gx * window.dy[k], gy, gy * window.dx[k], gy * window.dy[k], 1.0, g;
        // the lower triangle of a a^T, written out (Eigen's rankUpdate is slow at this fixed small size)
        for ( int c = 0; c < 8; ++c )
          for ( int r = c; r < 8; ++r )
            normal( r, c ) += a[r] * a[c];
        rhs += a * residual;
        sumSq += residual * residual;
      }
      return true;
    }

    //! Holds the shape parameters a1 a2 b1 b2 where they are (shifts and radiometry only).
    void fixShape( Normal &system, Parameters &rhs )
    {
      for ( int k : { 1, 2, 4, 5 } )
      {
        system.row( k ).setZero();
        system.col( k ).setZero();
        system( k, k ) = 1.0;
        rhs( k ) = 0.0;
      }
    }

    LsmResult failed( LsmResult result, LsmResult::Status status, const std::string &message )
    {
      result.status = status;
      result.message = message;
      return result;
    }
  } // namespace

  void LsmOptions::check() const
  {
    if ( windowWidth < 3 || windowHeight < 3 || windowWidth % 2 == 0 || windowHeight % 2 == 0 )
      throw std::invalid_argument( "the LSM window must have odd sizes of at least 3 (" + std::to_string( windowWidth ) + " x " + std::to_string( windowHeight ) + ")" );
    if ( maxIterations < 1 || !( convergencePx > 0.0 ) || !( referenceBlurPx >= 0.0 ) || !initialAffine.allFinite() )
      throw std::invalid_argument( "the LSM options need at least one iteration, a positive convergence threshold, a blur of 0 or more and a finite starting shape" );
  }

  std::string lsmStatusName( LsmResult::Status status )
  {
    switch ( status )
    {
      case LsmResult::Status::NotRun:
        return "not_run";
      case LsmResult::Status::Converged:
        return "converged";
      case LsmResult::Status::Outside:
        return "outside";
      case LsmResult::Status::Flat:
        return "flat";
      case LsmResult::Status::Diverged:
        return "diverged";
      case LsmResult::Status::NotConverged:
        return "not_converged";
    }
    return "unknown";
  }

  LsmResult leastSquaresMatch( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                               const Eigen::Vector2d &approximateInSearch, const LsmOptions &options )
  {
    options.check();
    LsmResult result;
    result.pixelInImage = approximateInSearch;
    TargetWindow window;
    if ( !readTarget( reference, pixelInReference, options, window ) )
      return failed( result, LsmResult::Status::Outside, "the window leaves the reference image" );
    const int n = window.size();
    const double maxShift = options.maxShiftPx > 0.0 ? options.maxShiftPx : std::max( options.windowWidth / 2, options.windowHeight / 2 );
    const bool bilinear = options.resampling == LsmOptions::Resampling::Bilinear;
    Parameters p;
    p << approximateInSearch.x(), options.initialAffine( 0, 0 ), options.initialAffine( 0, 1 ), approximateInSearch.y(), options.initialAffine( 1, 0 ),
      options.initialAffine( 1, 1 ), 0, 1;
    const double initialDet = options.initialAffine.determinant();
    if ( !( std::abs( initialDet ) > 1e-9 ) )
      return failed( result, LsmResult::Status::Diverged, "the starting shape is degenerate" );
    if ( gradientEnergy( search, window, p, bilinear ) < 0.25 * n )
      return failed( result, LsmResult::Status::Flat, "the window is flat (no texture to match)" );

    // shifts and radiometry first: freeing the shape parameters far from the
    // solution lets them absorb part of the shift and stop short of it
    Normal normal;
    double sumSq = 0.0;
    bool shapeFree = false, converged = false;
    for ( int iteration = 1; iteration <= options.maxIterations && !converged; ++iteration )
    {
      result.iterations = iteration;
      Parameters rhs;
      if ( !accumulate( search, window, p, bilinear, normal, rhs, sumSq ) )
        return failed( result, LsmResult::Status::Outside, "the window leaves the search image" );
      Normal system = normal.selfadjointView<Eigen::Lower>();
      if ( !shapeFree || !options.shape )
        fixShape( system, rhs );
      const Eigen::LDLT<Normal> ldlt( system );
      if ( ldlt.info() != Eigen::Success || !( ldlt.rcond() > 1e-12 ) )
        return failed( result, LsmResult::Status::Flat, "the window is flat (no texture to match)" );
      const Parameters dp = ldlt.solve( rhs );
      if ( !dp.allFinite() )
        return failed( result, LsmResult::Status::Diverged, "the solution diverged" );
      p += dp;
      // the area change against the starting shape (a predicted shape may itself scale the window strongly)
      const double det = ( Eigen::Matrix2d() << p[1], p[2], p[4], p[5] ).finished().determinant() / initialDet;
      if ( !( det > 0.2 && det < 5.0 ) || !( p[7] > 0.1 && p[7] < 10.0 ) )
        return failed( result, LsmResult::Status::Diverged, "the solution diverged (degenerate shape or contrast)" );
      if ( ( Eigen::Vector2d( p[0], p[3] ) - approximateInSearch ).norm() > maxShift )
        return failed( result, LsmResult::Status::Diverged, "the match moved out of the search window" );
      if ( !shapeFree && options.shape )
      {
        shapeFree = std::hypot( dp[0], dp[3] ) < 0.05 || iteration >= 4;
        continue;
      }
      // the bilinear surface has kinks at the pixel centres, where Gauss-Newton steps can cycle by a few
      // thousandths of a pixel: it converges at 0.01 px
      converged = std::hypot( dp[0], dp[3] ) < ( bilinear ? std::max( options.convergencePx, 0.01 ) : options.convergencePx );
    }
    result.pixelInImage = Eigen::Vector2d( p[0], p[3] );
    result.affine << p[1], p[2], p[4], p[5];
    result.h0 = p[6];
    result.h1 = p[7];
    result.sigma0 = std::sqrt( sumSq / std::max( 1, n - 8 ) );
    if ( !converged )
      return failed( result, LsmResult::Status::NotConverged, "no convergence in " + std::to_string( options.maxIterations ) + " iterations" );
    result.status = LsmResult::Status::Converged;
    const Normal covariance = normal.selfadjointView<Eigen::Lower>().toDenseMatrix().inverse() * ( result.sigma0 * result.sigma0 );
    result.sigmaPx = Eigen::Vector2d( std::sqrt( std::max( 0.0, covariance( 0, 0 ) ) ), std::sqrt( std::max( 0.0, covariance( 3, 3 ) ) ) );
    return result;
  }

} // namespace geostation
