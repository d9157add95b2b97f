/***************************************************************************
  controlprediction.h - the semi-automatic mode: predicted control found
  -------------------------------------------------------------------------
  Stokes' (1988) third alternative (§5): once the orientation is
  approximately known, the remaining control points are predicted in the
  photo, each is found in a small window around its prediction (the mark
  nearest the prediction; its centre by the grey-weighted centre of gravity
  of the disc), and all of them, with the points the operator measured, go
  into a robust resection. What the resection does not support is flagged,
  not dropped: the operator sees it and decides. The final orientation is
  taken from the operator's points and the found ones only; a found one it
  flags is left out and the orientation taken again.

    status found      a mark near the prediction, consistent with the rest
    status flagged    a mark was found but the resection disagrees with it
                      (normalised residual or residual too large) or
                      cannot check it (a low redundancy number: the other
                      points hardly constrain it), or a second mark is
                      almost as near the prediction
    status not_found  no mark in the window (hidden, covered, too small)
    status outside    predicted outside the frame or behind the camera

  Then, with the orientation from the first resection (good to a fraction
  of a pixel), every mark is located again right at its prediction, with
  the size the marks found so far have on the ground: a mark that is not
  there, or not of that size, is flagged or not found.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_CONTROLPREDICTION_H
#define GEOSTATION_IDENTIFICATION_CONTROLPREDICTION_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "adjustment/controlpoint.h"
#include "adjustment/resection.h"
#include "camera/camera.h"
#include "geometry/exteriororientation.h"
#include "identification/markcandidates.h"

namespace geostation
{

  struct ControlPredictionOptions
  {
    double searchRadiusPx = 25.0;    //!< window half-size around a prediction, pixels
    MarkCandidateOptions marks;      //!< mark detection in each window
    double sigmaPx = 0.5;            //!< σ of a found mark's centre, for the resection
    double flagResidualPx = 1.5;     //!< a found mark further than this from the resection's projection is flagged
    double flagNormalised = 3.5;     //!< ... or with a normalised residual (Baarda's w) above this
    double minRedundancy = 0.4;      //!< ... or whose redundancy number is below this (the other points hardly check it)
    double ambiguityRatio = 1.5;     //!< flagged when a second mark is within this times the nearest one's distance
    double refineTolerancePx = 2.0;  //!< second round: a mark located at its prediction must be this close to it
    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct PredictedPoint
  {
    enum class Status { Found, Flagged, NotFound, Outside };
    std::string pointId;
    Status status = Status::NotFound;
    std::string reason;                                       //!< why flagged or not found
    Eigen::Vector2d predictedPx = Eigen::Vector2d::Zero();   //!< from the final orientation
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();  //!< the mark's centre (Found, Flagged)
    Eigen::Vector2d residualPx = Eigen::Vector2d::Zero();    //!< projected - found, final resection
    double normalised = 0.0;                                  //!< Baarda's w in the final resection (0 if not in it)
    double diameterPx = 0.0;                                  //!< the detection's size of the mark
  };

  struct ControlPredictionSummary
  {
    std::vector<PredictedPoint> points;   //!< every control point not measured by the operator, in the control's order
    ResectionSummary resection;           //!< with the operator's points and the found ones (valid when ok())
    int found = 0, flagged = 0, notFound = 0, outside = 0;
    std::string message;
    bool ok() const { return resection.ok(); }
  };

  //! The status' name as tables write it: found, flagged, not_found, outside.
  std::string predictedPointStatusName( PredictedPoint::Status status );

  /**
   * Predicts every control point the operator has not measured from
   * `approximate`, finds it in `grey` (8-bit, the camera's nominal pixels)
   * and resects with `measured` and the found points. Throws
   * std::invalid_argument for bad options, a grey image of another size or
   * type than the camera's, or invalid control; an orientation the points
   * cannot give comes back in the resection's status.
   */
  ControlPredictionSummary predictAndFindControl( const cv::Mat &grey, const Camera &camera, const ExteriorOrientation &approximate,
      const std::vector<ControlPoint> &control, const std::vector<ImagePoint> &measured,
      const ControlPredictionOptions &options = ControlPredictionOptions() );

  /**
   * A scanned photo resampled (bicubic) into the camera's nominal frame,
   * where the camera model applies: `nominalFromScan` maps scan pixels to
   * nominal ones (nominalFromScanAffine()). 8-bit grey, the camera's size.
   */
  cv::Mat nominalImage( const cv::Mat &scanGrey, const Camera &camera, const Eigen::Matrix<double, 2, 3> &nominalFromScan );

  /**
   * A mark's centre to a fraction of a pixel: the centre of gravity of its
   * excess over half its contrast above the background around it,
   * recentred until it settles. `areaPx` receives the pixels above half
   * the contrast. Nothing when the window leaves the image or holds no mark.
   */
  std::optional<Eigen::Vector2d> markCentre( const cv::Mat &grey, const Eigen::Vector2d &approximate, double diameterPx, bool brightMark = true,
      double *areaPx = nullptr );

  /**
   * markCentre() for a disc whose outline is predicted: `discShape` maps the
   * unit circle to the outline's offsets from its centre, in pixels (a
   * target's radius on the ground times d(pixel)/d(ground)). The centre of
   * gravity is taken within the outline grown by 1 px, the background from a
   * ring beyond it, so a long ellipse seen at a grazing angle does not take
   * in what lies beside it.
   */
  std::optional<Eigen::Vector2d> markCentreInEllipse( const cv::Mat &grey, const Eigen::Vector2d &approximate, const Eigen::Matrix2d &discShape, bool brightMark = true,
      double *areaPx = nullptr );

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_CONTROLPREDICTION_H
