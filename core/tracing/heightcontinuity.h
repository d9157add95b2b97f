/***************************************************************************
  heightcontinuity.h - vertices that leave the road's height along a line
  -------------------------------------------------------------------------
  A road line follows the road surface, whose height changes smoothly
  along it: grades and vertical curves bend it over tens of metres, never
  by decimetres within one or two. A traced vertex whose height departs
  from the line through its neighbours' heights by more than its own
  sigma allows is a wrong conjugate that the adjustment could not expose:
  seen from the stations behind, nearly along the line, a point moved
  along its reference ray changes height but hardly moves across the
  line, so those images cannot contradict it.

  heightOutliers() fits z = a + b s to the neighbours' heights within
  `windowM` (s: horizontal distance along the line), leaves out the
  neighbour furthest from that fit when it stands out (beyond 4 robust
  sigmas of the others), and flags a vertex
  further from the fit than `sigmaMultiple` times its own and the fit's
  sigma combined, and at least `minStepM`. Nothing is flagged where fewer
  than `minNeighbours` vertices are near.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_HEIGHTCONTINUITY_H
#define GEOSTATION_TRACING_HEIGHTCONTINUITY_H

#include <vector>

#include <Eigen/Core>

namespace geostation
{

  struct HeightContinuityOptions
  {
    double windowM = 5.0;        //!< neighbours up to this far along the line, each side (m)
    int minNeighbours = 4;       //!< fewer near: not checked
    double minStepM = 0.08;      //!< never flagged for less than this (m): cross-fall changes, kerb drops
    double sigmaMultiple = 4.0;  //!< flagged beyond this many combined sigmas
  };

  /**
   * Indices of the vertices from `firstChecked` on whose height leaves the
   * line through their neighbours'; see the file comment. `points` in
   * order along the line (metres, z up), `sigmaZ` their height sigmas (m),
   * one per point. Throws std::invalid_argument when the sizes differ.
   */
  std::vector<size_t> heightOutliers( const std::vector<Eigen::Vector3d> &points, const std::vector<double> &sigmaZ, size_t firstChecked,
                                      const HeightContinuityOptions &options = HeightContinuityOptions() );

} // namespace geostation

#endif // GEOSTATION_TRACING_HEIGHTCONTINUITY_H
