/***************************************************************************
  photoorientation.h - one photo oriented interactively from control points
  -------------------------------------------------------------------------
  The core of the orientation dock (Stokes 1988, §4-5), without any
  GUI: the operator's control points - ground position, the pixel measured
  in the photo's file (scan pixels for scanned film), and whether each is
  used, a check point or off - go into a space resection after every
  change (orientPhoto()). The summary has, for every point in the list,
  where the orientation puts it in the file, its residual in pixels and on
  the ground, and Baarda's w. The worst point above the blunder threshold
  is left out of the solution and the rest solved again (data snooping),
  while it stays in the list, flagged with its w and its error on the
  ground, until the operator measures it again or switches it off.
  Points not yet measured
  get their predicted pixel, which is where the semi-automatic mode
  (offerPredictedControl()) looks for them.

  Pixels: the measured pixels are the image file's (docs/conventions.md §1); the
  camera model works in the nominal frame, reached through the scan
  affine of a scanned film's inner orientation (nominalFromScanAffine()).
  Residuals are reported in file pixels.
 ***************************************************************************/
#ifndef GEOSTATION_WORKSTATION_PHOTOORIENTATION_H
#define GEOSTATION_WORKSTATION_PHOTOORIENTATION_H

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "adjustment/interiorparameters.h"
#include "adjustment/resection.h"
#include "identification/controlprediction.h"

namespace geostation
{
  class Block;

  //! How a control point takes part in the orientation.
  enum class ControlRole
  {
    Control, //!< in the adjustment
    Check,   //!< evaluated only
    Off,     //!< ignored (kept in the list)
  };

  //! "control", "check", "off".
  std::string controlRoleName( ControlRole role );
  //! The role of a name controlRoleName() gives; nothing for anything else.
  std::optional<ControlRole> controlRoleFromName( const std::string &name );

  //! One row of the operator's control-point list.
  struct PhotoControlPoint
  {
    std::string pointId;
    Eigen::Vector3d world = Eigen::Vector3d::Zero();  //!< block CRS, metres
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero(); //!< 0: held fixed
    std::optional<Eigen::Vector2d> pixelInFile;       //!< measured (col, row of the image file); nothing: not yet
    double sigmaPx = 0.5;
    ControlRole role = ControlRole::Control;
  };

  struct PhotoOrientationOptions
  {
    std::array<bool, kInteriorSize> freeInterior {}; //!< f, cx, cy, k1, k2, p1, p2, k3 freed (all fixed by default)
    double blunderThreshold = 4.0; //!< Baarda's w above which a point is flagged
    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  //! A point of the list as the current orientation sees it.
  struct PhotoControlResult
  {
    std::string pointId;
    bool measured = false;
    std::optional<Eigen::Vector2d> projectedInFile;  //!< where the orientation puts it (file pixels); nothing: behind the camera
    bool inFrame = false;                            //!< projected into the photo
    std::optional<Eigen::Vector2d> residualPx;       //!< projected - measured, file pixels (measured control and check points)
    std::optional<Eigen::Vector3d> groundErrorM;     //!< check and flagged points: the measured ray at the point's height minus the point
    double normalised = 0.0;                         //!< Baarda's w (control points)
    bool blunder = false;                            //!< |w| above the threshold: left out of the solution
  };

  struct PhotoOrientationSummary
  {
    enum class Status
    {
      Oriented,
      NotEnoughPoints, //!< fewer measured control points than the free parameters need
      Failed,          //!< the resection's message says why (collinear control, no solution, ...)
    };
    Status status = Status::NotEnoughPoints;
    std::string message;          //!< one sentence for the dock
    int measuredControl = 0;      //!< measured points with the role Control
    int measuredCheck = 0;
    int neededControl = 4;        //!< for the free parameters
    ResectionSummary resection;   //!< valid when oriented
    std::vector<PhotoControlResult> points; //!< one per input point, same order
    bool oriented() const { return status == Status::Oriented; }
  };

  /**
   * Resects the photo from the measured points. `nominalFromFile` is the
   * scan affine of a scanned film (nothing: the file's pixels are the
   * camera's). Throws std::invalid_argument for bad options, a point id
   * used twice or a non-positive sigma; too few points, collinear control
   * and the like come back in the status with one sentence.
   */
  PhotoOrientationSummary orientPhoto( const Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile,
                                       const std::vector<PhotoControlPoint> &points, const PhotoOrientationOptions &options = PhotoOrientationOptions() );

  //! An offer of the semi-automatic mode: a control point found in the photo.
  struct ControlOffer
  {
    std::string pointId;
    PredictedPoint::Status status = PredictedPoint::Status::NotFound; //!< Found, Flagged (shown as such), NotFound, Outside
    std::string reason;
    Eigen::Vector2d pixelInFile = Eigen::Vector2d::Zero();     //!< the mark's centre (Found, Flagged)
    Eigen::Vector2d predictedInFile = Eigen::Vector2d::Zero();
  };

  /**
   * The semi-automatic mode: every point of `points` not measured yet
   * (role Control or Check) is predicted from `approximate`, looked for in
   * `greyFile` (the photo's file as 8-bit grey: markGrey()) and offered.
   * Nothing is accepted here: the operator accepts the offers.
   */
  std::vector<ControlOffer> offerPredictedControl( const cv::Mat &greyFile, const Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile,
      const ExteriorOrientation &approximate, const std::vector<PhotoControlPoint> &points,
      const ControlPredictionOptions &options = ControlPredictionOptions() );

  /**
   * Approximate orientations for the semi-automatic mode before four points
   * are measured (Stokes' (1988) alternatives): from three
   * measured points by P3P - its up to four solutions, those the other
   * measured points agree with best first - or from two points and the
   * camera's approximate position (`approximateCentre`, block CRS): the
   * rotation that turns the two rays onto the two points. Empty when
   * neither applies (or the geometry gives no solution). Which of several
   * is right, the photo decides: offerPredictedControl() with candidates.
   */
  std::vector<ExteriorOrientation> approximatePhotoOrientations( const Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile,
      const std::vector<PhotoControlPoint> &points, const std::optional<Eigen::Vector3d> &approximateCentre = std::nullopt );

  /**
   * offerPredictedControl() from each candidate orientation in turn; the
   * offers of the one under which the most marks are found (`chosen`
   * receives its index; -1 and no offers without candidates).
   */
  std::vector<ControlOffer> offerPredictedControl( const cv::Mat &greyFile, const Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile,
      const std::vector<ExteriorOrientation> &candidates, const std::vector<PhotoControlPoint> &points, int *chosen,
      const ControlPredictionOptions &options = ControlPredictionOptions() );

  /**
   * The operator-aided mode: the centre of the mark nearest to a clicked
   * pixel (file pixels), within `searchRadiusPx` and within the mark's own
   * size of the click (the click is on the mark: another mark nearby is
   * not taken for it), located by the mark detector (Förstner) and its
   * centre of gravity. Nothing when no mark is there.
   */
  std::optional<Eigen::Vector2d> refineMarkPixel( const cv::Mat &greyFile, const Eigen::Vector2d &clickedInFile, double searchRadiusPx = 15.0,
      const MarkCandidateOptions &marks = MarkCandidateOptions() );

  /**
   * Writes an orientation into the block: the image's exterior orientation
   * (with its sigmas) and, when interior parameters were freed, its
   * camera's interior. Throws std::invalid_argument for an unknown image or
   * a summary that is not oriented.
   */
  void applyPhotoOrientation( Block &block, const std::string &imageId, const PhotoOrientationSummary &summary, const PhotoOrientationOptions &options );

  /**
   * The operator's list as one CSV table that is both a docs/conventions.md §6
   * observation table (point_id, image_id, col, row, sigma_px, status:
   * `reference` for a measured point, `not_measured` otherwise) and a
   * ground-point table (X, Y, Z, role), so `geostation:resection` reruns
   * the orientation headless from it. Written atomically.
   */
  void writePhotoControlTable( const std::filesystem::path &file, const std::string &imageId, const std::vector<PhotoControlPoint> &points );
  //! Reads writePhotoControlTable()'s file; throws std::runtime_error naming the file and line.
  std::vector<PhotoControlPoint> readPhotoControlTable( const std::filesystem::path &file );

} // namespace geostation

#endif // GEOSTATION_WORKSTATION_PHOTOORIENTATION_H
