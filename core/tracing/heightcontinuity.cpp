/***************************************************************************
  heightcontinuity.cpp - vertices that leave the road's height along a line
 ***************************************************************************/
#include "tracing/heightcontinuity.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace geostation
{
  namespace
  {
    struct HeightFit
    {
      double a = 0.0, b = 0.0; //!< z = a + b (s - s0)
      double rms = 0.0;        //!< of the neighbours about the fit (m)
      int n = 0;
    };

    std::optional<HeightFit> fitHeights( const std::vector<double> &ds, const std::vector<double> &z )
    {
      const size_t n = ds.size();
      if ( n < 2 )
        return std::nullopt;
      double ms = 0.0, mz = 0.0;
      for ( size_t k = 0; k < n; ++k )
      {
        ms += ds[k];
        mz += z[k];
      }
      ms /= n;
      mz /= n;
      double sss = 0.0, ssz = 0.0;
      for ( size_t k = 0; k < n; ++k )
      {
        sss += ( ds[k] - ms ) * ( ds[k] - ms );
        ssz += ( ds[k] - ms ) * ( z[k] - mz );
      }
      HeightFit f;
      f.b = sss > 1e-6 ? ssz / sss : 0.0;
      f.a = mz - f.b * ms;
      double sum = 0.0;
      for ( size_t k = 0; k < n; ++k )
        sum += std::pow( z[k] - f.a - f.b * ds[k], 2 );
      f.rms = std::sqrt( sum / std::max<size_t>( 1, n > 2 ? n - 2 : 1 ) );
      f.n = static_cast<int>( n );
      return f;
    }
  }

  std::vector<size_t> heightOutliers( const std::vector<Eigen::Vector3d> &points, const std::vector<double> &sigmaZ, size_t firstChecked, const HeightContinuityOptions &options )
  {
    if ( points.size() != sigmaZ.size() )
      throw std::invalid_argument( "heightOutliers: one height sigma per point" );
    // horizontal distance along the line
    std::vector<double> along( points.size(), 0.0 );
    for ( size_t i = 1; i < points.size(); ++i )
      along[i] = along[i - 1] + ( points[i] - points[i - 1] ).head<2>().norm();
    std::vector<size_t> out;
    for ( size_t i = firstChecked; i < points.size(); ++i )
    {
      std::vector<double> ds, z;
      for ( size_t j = 0; j < points.size(); ++j )
        if ( j != i && std::abs( along[j] - along[i] ) <= options.windowM )
        {
          ds.push_back( along[j] - along[i] );
          z.push_back( points[j].z() );
        }
      if ( static_cast<int>( ds.size() ) < options.minNeighbours )
        continue;
      std::optional<HeightFit> fit = fitHeights( ds, z );
      if ( !fit )
        continue;
      // a neighbour that stands out (another wrong vertex) is left out of the fit: beyond 4 robust sigmas
      // (1.4826 x the median absolute residual) of the others
      std::vector<double> residuals;
      for ( size_t k = 0; k < ds.size(); ++k )
        residuals.push_back( std::abs( z[k] - fit->a - fit->b * ds[k] ) );
      const size_t worst = static_cast<size_t>( std::max_element( residuals.begin(), residuals.end() ) - residuals.begin() );
      const double worstResidual = residuals[worst];
      std::nth_element( residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end() );
      const double robustSigma = 1.4826 * residuals[residuals.size() / 2];
      if ( static_cast<int>( ds.size() ) > options.minNeighbours && worstResidual > std::max( 0.5 * options.minStepM, 4.0 * robustSigma ) )
      {
        ds.erase( ds.begin() + static_cast<std::ptrdiff_t>( worst ) );
        z.erase( z.begin() + static_cast<std::ptrdiff_t>( worst ) );
        fit = fitHeights( ds, z );
        if ( !fit )
          continue;
      }
      const double offset = std::abs( points[i].z() - fit->a );
      const double sigma = std::hypot( sigmaZ[i], fit->rms );
      if ( offset > std::max( options.minStepM, options.sigmaMultiple * sigma ) )
        out.push_back( i );
    }
    return out;
  }

} // namespace geostation
