/***************************************************************************
  multiimagematcher.h - matching a point in more than two images (thesis §5.4)
  -------------------------------------------------------------------------
  1. The master pair (the reference image and the master image) is matched
     along the epipolar band; its best separate correlation peaks are the
     candidates.
  2. Each candidate is intersected with the reference ray,
  3. projected into the other images,
  4. and searched for in a small window there (along its epipolar line);
  5. a candidate that any image does not confirm (score below the
     threshold) is rejected, as is one outside the depth range;
  6. the best confirmed candidate is re-intersected from all its rays.
  Feature support: when the reference point is on an edge (strong
  gradient), every match must be on an edge too.
  On repetitive texture this removes the wrong peaks a single pair cannot
  tell from the right one.
 ***************************************************************************/
#ifndef GEOSTATION_MATCHING_MULTIIMAGEMATCHER_H
#define GEOSTATION_MATCHING_MULTIIMAGEMATCHER_H

#include <optional>
#include <string>
#include <vector>

#include "geometry/epipolar.h"
#include "matching/areamatcher.h"

namespace geostation
{

  struct MatchView
  {
    const OrientedImage *image = nullptr;
    const MatchImage *pixels = nullptr;
  };

  struct MultiImageMatchOptions
  {
    AreaMatchOptions area;          //!< correlation, window, threshold, LSM
    EpipolarOptions epipolar;       //!< the depth range of the master-pair search
    int candidates = 5;             //!< master-pair peaks tried
    double confirmRadiusPx = 2.0;   //!< search radius around the back-projection in the other images
    bool edgeConstraint = true;     //!< feature support: edge points match edge points
    double edgeGradient = 40.0;     //!< Sobel magnitude (grey levels) that makes a point an edge point
  };

  struct MultiImageMatch
  {
    //! The master pair's match status when confirmed; Outside (no ray), the master pair's failure, or Inconsistent (no candidate confirmed).
    MatchStatus status = MatchStatus::NoPeak;
    std::string message;                                     //!< why not, when not matched
    Eigen::Vector3d world = Eigen::Vector3d::Zero();         //!< block CRS
    std::vector<std::optional<Eigen::Vector2d>> pixels;      //!< per view (the reference's own pixel too)
    std::vector<double> scores;                              //!< per view (1 for the reference)
    int candidatesTried = 0;

    bool matched() const { return isMatch( status ); }
  };

  //! The least-squares point nearest to all rays (origin + t direction, unit directions).
  std::optional<Eigen::Vector3d> nearestPointToRays( const std::vector<Ray> &rays );

  /**
   * Matches `pixelInReference` of view `reference` in the master view along
   * its epipolar curve and keeps the candidate the other views confirm.
   * Throws std::invalid_argument unless reference and master are two
   * different views.
   */
  MultiImageMatch matchMultiImage( const std::vector<MatchView> &views, size_t reference, size_t master, const Eigen::Vector2d &pixelInReference,
                                   const MultiImageMatchOptions &options );

} // namespace geostation

#endif // GEOSTATION_MATCHING_MULTIIMAGEMATCHER_H
