/***************************************************************************
  falsealarms.h - could chance explain an identification? (a contrario)
  -------------------------------------------------------------------------
  A pose chosen among hundreds of thousands can always line a few control
  points up with candidates where candidates are dense (texture, a row of
  marks along a road). An identification is accepted only when its number
  of false alarms - the tests made times the probability that as many
  control points fall on candidates by chance - stays small.

  The chance for one predicted point is the candidates around it (within a
  density radius, without the one it matched) times the share of that
  circle the matching radius covers; the count of chance matches is
  Poisson with the sum of these over the control predicted in the frame.
  The three points a pose is fitted to do not count. The matching radius is
  the tolerance itself, not the (smaller) residuals after the resection:
  the resection pulls the points it is fitted to together, wrong ones too.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_FALSEALARMS_H
#define GEOSTATION_IDENTIFICATION_FALSEALARMS_H

#include <vector>

#include <Eigen/Core>

namespace geostation
{

  //! P(X >= m) for X ~ Poisson(lambda).
  double poissonTail( double lambda, int m );

  /**
   * The number of false alarms of an identification. `predictedPx`: every
   * control point the solution puts in the frame; `pairResidualsPx`: the
   * distance of each identified pair's candidate from its prediction;
   * `tests`: the hypotheses tried.
   */
  double identificationFalseAlarms( const std::vector<Eigen::Vector2d> &predictedPx, const std::vector<Eigen::Vector2d> &candidatesPx,
                                    const std::vector<double> &pairResidualsPx, double tolerancePx, double densityRadiusPx, double tests );

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_FALSEALARMS_H
