/***************************************************************************
  resection.h - space resection of one image from control points
  -------------------------------------------------------------------------
  Exterior orientation (and optionally interior parameters) of one image from
  four or more control points, by least squares on the collinearity
  equations (Ceres), starting from an automatic closed-form solution (SQPnP
  on the undistorted rays) so no approximate orientation is needed.
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_RESECTION_H
#define GEOSTATION_ADJUSTMENT_RESECTION_H

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adjustment/controlpoint.h"
#include "adjustment/interiorparameters.h"
#include "camera/camera.h"
#include "geometry/exteriororientation.h"

namespace geostation
{

  struct ResectionOptions
  {
    std::array<bool, kInteriorSize> freeInterior {}; //!< all fixed by default
    bool robust = false;            //!< Huber loss while iterating (statistics use plain least squares)
    double robustThreshold = 2.0;   //!< in sigmas
    double blunderThreshold = 4.0;  //!< Baarda's w above which a point is a blunder
    bool removeBlunders = true;     //!< drop the worst blunder and solve again, while enough points remain
    bool scaleCovarianceBySigma0 = true;
    int maxIterations = 100;
    //! Convergence: relative change of the cost, gradient (max norm) and parameters (Ceres' tolerances).
    double functionTolerance = 1e-14;
    double gradientTolerance = 1e-14;
    double parameterTolerance = 1e-12;
    std::optional<ExteriorOrientation> initial; //!< skip the automatic start

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct PointResidual
  {
    std::string pointId;
    Eigen::Vector2d residualPx = Eigen::Vector2d::Zero(); //!< projected - observed
    double normalised = 0.0;   //!< Baarda's w (control points used in the adjustment)
    //! The smaller redundancy number of its two coordinates (control points used): the share of an error in
    //! it that shows in its residual - 0 where the other points do not check it at all, 1 where they fix it.
    double redundancy = 1.0;
    bool check = false;
    bool blunder = false;      //!< flagged; removed from the solution when removeBlunders
    //! Check and blunder points: error on the ground, the observed ray cut at the
    //! point's known height, minus the known point (metres; Z = 0).
    Eigen::Vector3d groundErrorM = Eigen::Vector3d::Zero();
  };

  struct ResectionSummary
  {
    enum class Status
    {
      Ok,
      TooFewPoints,
      DegenerateControl, //!< collinear control, or parameters the geometry cannot separate
      NoSolution,        //!< no starting orientation puts the control in front of the camera
      NotConverged,
    };
    Status status = Status::Ok;
    std::string message;

    ExteriorOrientation exterior; //!< with sigma filled from the adjustment
    Camera camera;                //!< interior as estimated (unchanged when all fixed)
    std::vector<std::string> parameterNames; //!< X0, Y0, Z0, omega, phi, kappa, then the free interior
    std::vector<double> estimates;           //!< metres, degrees, pixels, model units
    std::vector<double> sigmas;
    Eigen::MatrixXd correlation;
    double sigma0 = 0.0;
    int redundancy = 0;
    int iterations = 0;
    bool converged = false;
    std::vector<PointResidual> residuals; //!< control, then check points
    std::vector<std::string> blunders;    //!< removed, worst first
    double rmseControlPx = 0.0;
    double rmseCheckPx = 0.0;
    double rmseCheckM = 0.0;  //!< planimetric, at the check points' heights
    int controlCount = 0;     //!< used in the final solution
    int checkCount = 0;
    int unmatchedObservations = 0; //!< image points without a control point

    bool ok() const { return status == Status::Ok; }
  };

  /**
   * Resects one image. Throws std::invalid_argument on inconsistent input
   * (invalid camera, non-positive sigma, a point measured twice, freeing lens
   * coefficients of a camera without lens model); expected failures are
   * reported in the summary's status and message.
   */
  ResectionSummary resectImage( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<ImagePoint> &observations,
                                const ResectionOptions &options = ResectionOptions() );

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_RESECTION_H
