/***************************************************************************
  pointmeasurer.h - one 3D vertex from a click in one image (thesis ch. 2)
  -------------------------------------------------------------------------
  The Multiview's measurement loop, without any GUI:
  1. proposeConjugates(): the epipolar curve of the clicked pixel in every
     other view and, where the images can be matched, the proposed
     conjugate point with its score. All views that see the curve are
     matched together (multi-image matching: a candidate must be confirmed
     in every view); when that fails (the point is hidden in one view),
     each view is matched with the reference alone.
  2. The operator accepts or corrects the proposals; then
     intersectVertex() intersects the rays (two or more) with standard
     deviations and pixel residuals, or, for an object seen in one image
     only, roadPlaneVertex() / demVertex() give a single-ray vertex, marked
     by its method.
 ***************************************************************************/
#ifndef GEOSTATION_WORKSTATION_POINTMEASURER_H
#define GEOSTATION_WORKSTATION_POINTMEASURER_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adjustment/intersection.h"
#include "geometry/epipolar.h"
#include "geometry/windowshape.h"
#include "matching/multiimagematcher.h"

namespace geostation
{
  class Monoplotter;

  //! An image shown in a view.
  struct MeasurementView
  {
    std::string imageId;
    const OrientedImage *image = nullptr; //!< nullptr: not oriented (no curve, no match)
    const MatchImage *pixels = nullptr;   //!< nullptr: image not readable (curve only)
  };

  struct ProposalOptions
  {
    EpipolarOptions epipolar { 1.5, 80.0, 2.0, 20000 }; //!< the depth range searched (metres along the ray)
    AreaMatchOptions area;       //!< correlation window, threshold, LSM
    bool multiImage = true;      //!< confirm candidates in all views that see the curve
    //! A match farther from the reference pixel's epipolar curve than this (px) is inconsistent with the orientation.
    double maxEpipolarDistancePx = 3.0;
    /**
     * With three or more rays, the proposals are intersected with the
     * reference ray; a residual beyond this (px, and beyond 3 of its
     * sigmas) makes a proposal inconsistent (flagInconsistentProposals();
     * thesis §5.4: the other images' geometry confirms a match).
     */
    double maxIntersectionResidualPx = 2.0;
    /**
     * The surface the measured points lie on, if known (road plane, DEM).
     * The correlation window's shape in each view is then predicted from it
     * (predictWindowShape()), so oblique and close-range views correlate on
     * like-shaped patches; points off the surface keep the square window
     * (AreaMatchOptions::predictedShape).
     */
    GroundOfPixel groundOfPixel;
  };

  struct ConjugateProposal
  {
    std::string imageId;
    EpipolarCurve curve;           //!< of the reference pixel, in this view
    bool curveInFrame = false;     //!< some of the curve lies in the frame
    /**
     * docs/conventions.md §8: Lsm (least squares converged and passed its checks),
     * Correlation (a peak only: to be checked by the operator, never
     * pre-accepted), or why there is no proposal (NoPeak, Ambiguous,
     * Diverged, Inconsistent, Outside - also for a view that is not
     * oriented, cannot be read or does not see the curve).
     */
    MatchStatus status = MatchStatus::Outside;
    std::string message;           //!< why not matched
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    double score = 0.0;
    double sigmaPx = 0.5;

    bool matched() const { return isMatch( status ); }
  };

  /**
   * Curves and proposed conjugate points of `pixelInReference` for every view
   * except the reference (in view order; the reference's entry is empty).
   * Throws std::invalid_argument if the reference is out of range or not
   * oriented.
   */
  std::vector<ConjugateProposal> proposeConjugates( const std::vector<MeasurementView> &views, size_t reference, const Eigen::Vector2d &pixelInReference,
      const ProposalOptions &options = ProposalOptions() );

  /**
   * With three or more rays (the reference and the matched proposals), the
   * proposals are intersected with the reference ray. A residual above
   * ProposalOptions::maxIntersectionResidualPx and 3 of its sigmas means a
   * wrong proposal: with four or more rays the one with the largest such
   * residual is marked inconsistent (not matched) and the rest intersected
   * again; with three rays the two proposals contradict each other and
   * which one is wrong cannot be told (both lie on epipolar curves of the
   * reference pixel), so both are marked inconsistent for the operator to
   * decide. proposeConjugates() calls it last.
   */
  void flagInconsistentProposals( const std::vector<MeasurementView> &views, size_t reference, const Eigen::Vector2d &pixelInReference,
                                  const ProposalOptions &options, std::vector<ConjugateProposal> &proposals );

  enum class VertexMethod
  {
    Intersection,
    MonoplotDem,
    RoadPlane,
  };

  //! "intersection", "monoplot-DEM", "road-plane" (docs/conventions.md §7)
  std::string vertexMethodName( VertexMethod method );

  struct VertexObservation
  {
    std::string imageId;
    const OrientedImage *image = nullptr;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    double sigmaPx = 0.5;
  };

  struct MeasuredVertex
  {
    enum class Status
    {
      Ok,
      Suspect,       //!< intersected, but one ray may carry a gross error (message names it)
      NoIntersection, //!< the rays do not give a point (too few, parallel, singular)
      MissesSurface, //!< the single ray does not meet the road plane or the DEM
    };
    Status status = Status::NoIntersection;
    std::string message;                       //!< one sentence when not ok; the warning when Suspect
    VertexMethod method = VertexMethod::Intersection;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  //!< block CRS, metres
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    std::vector<std::string> imageIds;
    std::vector<Eigen::Vector2d> residualsPx;  //!< per image (projected - observed); zero for a single ray
    double rmsPx = 0.0;
    double maxRayAngleDeg = 0.0;
    double rangeM = 0.0;                       //!< from the nearest projection centre

    //! A point was measured (Suspect included).
    bool ok() const { return status == Status::Ok || status == Status::Suspect; }
  };

  //! Two or more rays. Throws like intersectRays().
  MeasuredVertex intersectVertex( const std::vector<VertexObservation> &observations, const IntersectionOptions &options = IntersectionOptions() );

  /**
   * One ray and the road plane: the horizontal plane `roadHeightM` (block
   * CRS Z), e.g. the projection centre's height minus the camera's height
   * above the road, with its sigma.
   */
  MeasuredVertex roadPlaneVertex( const VertexObservation &observation, double roadHeightM, double planeSigmaM );

  //! One ray and the DEM, through a monoplotter of the observation's image.
  MeasuredVertex demVertex( const VertexObservation &observation, const Monoplotter &monoplotter );

  /**
   * A line digitised in one image, densified on the terrain: the ground
   * under the image segment from `from` to `toPixel` (same image), a DEM
   * vertex every `stepPx` pixels along it, the two ends left out (they are
   * the operator's vertices). Pixels whose rays miss the DEM are left out.
   * Throws std::invalid_argument if stepPx <= 0.
   */
  std::vector<MeasuredVertex> demVerticesBetween( const VertexObservation &from, const Eigen::Vector2d &toPixel, const Monoplotter &monoplotter, double stepPx );

} // namespace geostation

#endif // GEOSTATION_WORKSTATION_POINTMEASURER_H
