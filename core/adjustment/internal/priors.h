/***************************************************************************
  priors.h - prior observations of parameters, as Ceres cost functors
  -------------------------------------------------------------------------
  (value - known) / sigma for each component with sigma > 0; components with
  sigma = 0 are held fixed by the caller (fixedComponents) and contribute a
  zero residual here.
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_PRIORS_H
#define GEOSTATION_ADJUSTMENT_PRIORS_H

#include <array>
#include <vector>

#include <ceres/autodiff_cost_function.h>

namespace geostation
{

  template <int N>
  struct ParameterPrior
  {
    ParameterPrior( const std::array<double, N> &known, const std::array<double, N> &sigma ) : mKnown( known ), mSigma( sigma ) {}

    template <typename T>
    bool operator()( const T *value, T *residuals ) const
    {
      for ( int k = 0; k < N; ++k )
        residuals[k] = mSigma[k] > 0.0 ? ( value[k] - T( mKnown[k] ) ) / T( mSigma[k] ) : T( 0.0 );
      return true;
    }

    static ceres::CostFunction *create( const std::array<double, N> &known, const std::array<double, N> &sigma )
    {
      return new ceres::AutoDiffCostFunction<ParameterPrior<N>, N, N>( new ParameterPrior<N>( known, sigma ) );
    }

    //! Indices of the components that carry no prior and are held fixed (sigma = 0).
    static std::vector<int> fixedComponents( const std::array<double, N> &sigma )
    {
      std::vector<int> fixed;
      for ( int k = 0; k < N; ++k )
        if ( !( sigma[k] > 0.0 ) )
          fixed.push_back( k );
      return fixed;
    }

    std::array<double, N> mKnown, mSigma;
  };

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_PRIORS_H
