/***************************************************************************
  falsealarms.cpp - could chance explain an identification? (a contrario)
 ***************************************************************************/
#include "identification/falsealarms.h"

#include <algorithm>
#include <cmath>

namespace geostation
{

  double poissonTail( double lambda, int m )
  {
    if ( m <= 0 )
      return 1.0;
    if ( !( lambda > 0.0 ) )
      return 0.0;
    double term = std::exp( -lambda + m * std::log( lambda ) - std::lgamma( m + 1.0 ) ), sum = 0.0;
    for ( int i = m; i < m + 400 && term > 1e-300; ++i )
    {
      sum += term;
      term *= lambda / ( i + 1 );
    }
    return std::min( 1.0, sum );
  }

  double identificationFalseAlarms( const std::vector<Eigen::Vector2d> &predictedPx, const std::vector<Eigen::Vector2d> &candidatesPx,
                                    const std::vector<double> &pairResidualsPx, double tolerancePx, double densityRadiusPx, double tests )
  {
    std::vector<int> around;
    std::vector<double> nearest;
    for ( const Eigen::Vector2d &predicted : predictedPx )
    {
      int near = 0;
      double closest = 1e300;
      for ( const Eigen::Vector2d &p : candidatesPx )
      {
        const double d = ( p - predicted ).norm();
        near += d <= densityRadiusPx ? 1 : 0;
        closest = std::min( closest, d );
      }
      around.push_back( near );
      nearest.push_back( closest );
    }
    // one radius, the tolerance: the resection pulls the points it is fitted to inside any smaller one
    const double radius = tolerancePx;
    {
      double lambda = 0.0;
      for ( size_t k = 0; k < around.size(); ++k )
        lambda += std::min( 1.0, ( around[k] - ( nearest[k] <= radius ? 1 : 0 ) ) * radius * radius / ( densityRadiusPx * densityRadiusPx ) );
      const int within = static_cast<int>( std::count_if( pairResidualsPx.begin(), pairResidualsPx.end(), [&]( double r ) { return r <= radius; } ) );
      return std::max( 1.0, tests ) * poissonTail( lambda, within - 3 );
    }
  }

} // namespace geostation
