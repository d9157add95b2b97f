// Matching scored against known truth: of the attempted points, how many
// came back as matches (lsm or correlation), how many lie within 1 px, the
// median error of the returned ones, and how many returned matches are more
// than 2 px off (wrong matches passed off as right), with the statuses.
#ifndef GEOSTATION_TESTS_MATCHSCORE_H
#define GEOSTATION_TESTS_MATCHSCORE_H

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace geostation
{
  struct MatchScore
  {
    int attempted = 0, returned = 0, within1 = 0, wrongReturned = 0;
    double median = 0.0;
    std::map<std::string, int> statuses;
    std::vector<double> errors; //!< of the returned matches, px
    std::vector<double> sigmas; //!< the sigmas the returned matches claim, px

    double within1Fraction() const { return attempted ? static_cast<double>( within1 ) / attempted : 0.0; }
    double wrongFraction() const { return returned ? static_cast<double>( wrongReturned ) / returned : 0.0; }

    /**
     * The returned matches' error over the sigma they claim: the RMS of
     * error / sigma (about 1.4 for sigmas that are right: the error is 2-D,
     * the sigma the larger of the two shifts'), and the worst.
     */
    double rmsErrorOverSigma() const
    {
      double sum = 0.0;
      for ( size_t i = 0; i < errors.size() && i < sigmas.size(); ++i )
        sum += ( errors[i] / sigmas[i] ) * ( errors[i] / sigmas[i] );
      return sigmas.empty() ? 0.0 : std::sqrt( sum / std::min( errors.size(), sigmas.size() ) );
    }
    double worstErrorOverSigma() const
    {
      double worst = 0.0;
      for ( size_t i = 0; i < errors.size() && i < sigmas.size(); ++i )
        worst = std::max( worst, errors[i] / sigmas[i] );
      return worst;
    }

    //! One attempted point: its status, and its error (and the sigma it claims, when known) when it was returned as a match.
    void add( const std::string &status, bool matched, double errorPx, double sigmaPx = 0.0 )
    {
      ++attempted;
      ++statuses[status];
      if ( !matched )
        return;
      ++returned;
      if ( sigmaPx > 0.0 )
        sigmas.push_back( sigmaPx );
      errors.push_back( errorPx );
      within1 += errorPx <= 1.0;
      wrongReturned += errorPx > 2.0;
      std::vector<double> sorted = errors;
      std::nth_element( sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end() );
      median = sorted[sorted.size() / 2];
    }

    void print( const std::string &name ) const
    {
      std::printf( "%-44s attempted %3d returned %3d  within 1 px %5.1f %%  median %.2f px  returned > 2 px off %4.1f %%  (", name.c_str(), attempted, returned,
                   100.0 * within1Fraction(), median, 100.0 * wrongFraction() );
      for ( const auto &[status, n] : statuses )
        std::printf( " %s %d", status.c_str(), n );
      std::printf( " )" );
      if ( !sigmas.empty() )
        std::printf( "  error / sigma: RMS %.2f, worst %.1f", rmsErrorOverSigma(), worstErrorOverSigma() );
      std::printf( "\n" );
    }
  };
}

#endif
