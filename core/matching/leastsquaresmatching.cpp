/***************************************************************************
  leastsquaresmatching.cpp - affine + radiometric least-squares matching
 ***************************************************************************/
#include "matching/leastsquaresmatching.h"

#include <cmath>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace geostation
{

  LsmResult leastSquaresMatch( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                               const Eigen::Vector2d &approximateInSearch, const LsmOptions &options )
  {
    LsmResult result;
    result.pixelInImage = approximateInSearch;
    const int hw = options.windowWidth / 2, hh = options.windowHeight / 2;
    if ( options.windowWidth < 3 || options.windowHeight < 3 || options.windowWidth % 2 == 0 || options.windowHeight % 2 == 0 )
    {
      result.reason = "the LSM window must have odd sizes of at least 3";
      return result;
    }
    const double maxShift = options.maxShiftPx > 0.0 ? options.maxShiftPx : std::max( hw, hh );
    const int n = options.windowWidth * options.windowHeight;

    // the target window: the reference pixels themselves (no resampling, which would smooth them),
    // centred on the pixel holding the reference point; (dx, dy) are offsets from the point itself
    std::vector<double> target( n ), dx( n ), dy( n );
    const int centreCol = static_cast<int>( std::floor( pixelInReference.x() ) ), centreRow = static_cast<int>( std::floor( pixelInReference.y() ) );
    if ( centreCol - hw < 0 || centreRow - hh < 0 || centreCol + hw >= reference.width() || centreRow + hh >= reference.height() )
    {
      result.reason = "the window leaves the reference image";
      return result;
    }
    // the optional smoothing kernel (clipped at the image border)
    const int blurRadius = options.referenceBlurPx > 0.0 ? static_cast<int>( std::ceil( 3.0 * options.referenceBlurPx ) ) : 0;
    std::vector<double> kernel( 2 * blurRadius + 1, 1.0 );
    for ( int i = -blurRadius; i <= blurRadius && blurRadius > 0; ++i )
      kernel[i + blurRadius] = std::exp( -0.5 * i * i / ( options.referenceBlurPx * options.referenceBlurPx ) );
    const auto referenceValue = [&]( int row, int col ) -> double
    {
      if ( blurRadius == 0 )
        return reference.value().at<float>( row, col );
      double sum = 0.0, weights = 0.0;
      for ( int i = -blurRadius; i <= blurRadius; ++i )
        for ( int j = -blurRadius; j <= blurRadius; ++j )
          if ( row + i >= 0 && col + j >= 0 && row + i < reference.height() && col + j < reference.width() )
          {
            const double w = kernel[i + blurRadius] * kernel[j + blurRadius];
            sum += w * reference.value().at<float>( row + i, col + j );
            weights += w;
          }
      return sum / weights;
    };
    for ( int r = -hh, k = 0; r <= hh; ++r )
      for ( int c = -hw; c <= hw; ++c, ++k )
      {
        target[k] = referenceValue( centreRow + r, centreCol + c );
        dx[k] = centreCol + c + 0.5 - pixelInReference.x();
        dy[k] = centreRow + r + 0.5 - pixelInReference.y();
      }

    const bool bilinear = options.resampling == LsmOptions::Resampling::Bilinear;
    // parameters: a0 a1 a2 b0 b1 b2 h0 h1
    Eigen::Matrix<double, 8, 1> p;
    p << approximateInSearch.x(), options.initialAffine( 0, 0 ), options.initialAffine( 0, 1 ), approximateInSearch.y(), options.initialAffine( 1, 0 ),
      options.initialAffine( 1, 1 ), 0, 1;
    const double initialDet = options.initialAffine.determinant();
    if ( !( std::abs( initialDet ) > 1e-9 ) )
    {
      result.reason = "the starting shape is degenerate";
      return result;
    }
    Eigen::Matrix<double, 8, 8> normal;
    double sumSq = 0.0;
    double gradientEnergy = 0.0;
    for ( int k = 0; k < n; ++k )
    {
      const double col = p[0] + p[1] * dx[k] + p[2] * dy[k], row = p[3] + p[4] * dx[k] + p[5] * dy[k];
      float dCol = 0, dRow = 0;
      if ( search.canSampleCubic( col, row ) )
      {
        if ( bilinear )
          search.sampleBilinear( col, row, &dCol, &dRow );
        else
          search.sampleCubic( col, row, &dCol, &dRow );
        gradientEnergy += static_cast<double>( dCol ) * dCol + static_cast<double>( dRow ) * dRow;
      }
    }
    if ( gradientEnergy < 0.25 * n )
    {
      result.reason = "the window is flat (no texture to match)";
      result.degenerate = true;
      return result;
    }
    // shifts and radiometry first: freeing the shape parameters far from the
    // solution lets them absorb part of the shift and stop short of it
    bool shapeFree = false;
    for ( int iteration = 1; iteration <= options.maxIterations; ++iteration )
    {
      result.iterations = iteration;
      normal.setZero();
      Eigen::Matrix<double, 8, 1> rhs = Eigen::Matrix<double, 8, 1>::Zero();
      sumSq = 0.0;
      for ( int k = 0; k < n; ++k )
      {
        const double col = p[0] + p[1] * dx[k] + p[2] * dy[k], row = p[3] + p[4] * dx[k] + p[5] * dy[k];
        if ( !search.canSampleCubic( col, row ) )
        {
          result.reason = "the window leaves the search image";
          return result;
        }
        float dCol = 0, dRow = 0;
        const double g = bilinear ? search.sampleBilinear( col, row, &dCol, &dRow ) : search.sampleCubic( col, row, &dCol, &dRow );
        const double gx = p[7] * dCol, gy = p[7] * dRow;
        const double residual = target[k] - ( p[6] + p[7] * g );
        Eigen::Matrix<double, 8, 1> a;
        a << gx, gx * dx[k], gx * dy[k], gy, gy * dx[k], gy * dy[k], 1.0, g;
        // the lower triangle of a a^T, written out (Eigen's rankUpdate is slow at this fixed small size)
        for ( int c = 0; c < 8; ++c )
          for ( int r = c; r < 8; ++r )
            normal( r, c ) += a[r] * a[c];
        rhs += a * residual;
        sumSq += residual * residual;
      }
      Eigen::Matrix<double, 8, 8> system = normal.selfadjointView<Eigen::Lower>();
      if ( !shapeFree || !options.shape )
        for ( int k : { 1, 2, 4, 5 } )
        {
          system.row( k ).setZero();
          system.col( k ).setZero();
          system( k, k ) = 1.0;
          rhs( k ) = 0.0;
        }
      const Eigen::LDLT<Eigen::Matrix<double, 8, 8>> ldlt( system );
      if ( ldlt.info() != Eigen::Success || !( ldlt.rcond() > 1e-12 ) )
      {
        result.reason = "the window is flat (no texture to match)";
        result.degenerate = true;
        return result;
      }
      const Eigen::Matrix<double, 8, 1> dp = ldlt.solve( rhs );
      if ( !dp.allFinite() )
      {
        result.reason = "the solution diverged";
        return result;
      }
      p += dp;
      // the area change against the starting shape (a predicted shape may itself scale the window strongly)
      const Eigen::Matrix2d affine = ( Eigen::Matrix2d() << p[1], p[2], p[4], p[5] ).finished();
      const double det = affine.determinant() / initialDet;
      if ( !( det > 0.2 && det < 5.0 ) || !( p[7] > 0.1 && p[7] < 10.0 ) )
      {
        result.reason = "the solution diverged (degenerate shape or contrast)";
        return result;
      }
      if ( ( Eigen::Vector2d( p[0], p[3] ) - approximateInSearch ).norm() > maxShift )
      {
        result.reason = "the match moved out of the search window";
        return result;
      }
      if ( !shapeFree && options.shape )
      {
        if ( std::hypot( dp[0], dp[3] ) < 0.05 || iteration >= 4 )
          shapeFree = true;
        continue;
      }
      // the bilinear surface has kinks at the pixel centres, where Gauss-Newton steps can cycle by a few
      // thousandths of a pixel: it converges at 0.01 px
      if ( std::hypot( dp[0], dp[3] ) < ( bilinear ? std::max( options.convergencePx, 0.01 ) : options.convergencePx ) )
      {
        result.converged = true;
        break;
      }
    }
    result.pixelInImage = Eigen::Vector2d( p[0], p[3] );
    result.affine << p[1], p[2], p[4], p[5];
    result.h0 = p[6];
    result.h1 = p[7];
    result.sigma0 = std::sqrt( sumSq / std::max( 1, n - 8 ) );
    if ( !result.converged )
    {
      result.reason = "no convergence in " + std::to_string( options.maxIterations ) + " iterations";
      return result;
    }
    const Eigen::Matrix<double, 8, 8> covariance = normal.selfadjointView<Eigen::Lower>().toDenseMatrix().inverse() * ( result.sigma0 * result.sigma0 );
    result.sigmaPx = Eigen::Vector2d( std::sqrt( std::max( 0.0, covariance( 0, 0 ) ) ), std::sqrt( std::max( 0.0, covariance( 3, 3 ) ) ) );
    return result;
  }

} // namespace geostation
