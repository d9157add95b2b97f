/***************************************************************************
  bundleadjustment.h - bundle adjustment of a block (thesis §3.3, eq. 3.13)
  -------------------------------------------------------------------------
  Simultaneous least squares over all images, tie points and control:
  exterior orientations (with GNSS/INS priors), optionally interior
  parameters per camera (self-calibration), and every point's position with
  its precision. Check points are adjusted as tie points and compared with
  their known coordinates.
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_BUNDLEADJUSTMENT_H
#define GEOSTATION_ADJUSTMENT_BUNDLEADJUSTMENT_H

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adjustment/controlpoint.h"
#include "adjustment/interiorparameters.h"
#include "camera/camera.h"
#include "geometry/exteriororientation.h"
#include "progress/progress.h"

namespace geostation
{

  //! An image taking part: its camera and its (approximate) orientation.
  struct BundleImage
  {
    std::string id;
    std::string cameraId;
    ExteriorOrientation exterior; //!< start values; sigma = GNSS/INS priors
  };

  //! One measured image point.
  struct BundleObservation
  {
    std::string pointId;
    std::string imageId;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    double sigmaPx = 0.5;
  };

  struct BundleOptions
  {
    std::array<bool, kInteriorSize> freeInterior {}; //!< self-calibration, for every camera
    bool usePosePriors = true;    //!< the images' exterior sigmas as observations
    bool robust = false;          //!< Huber loss while iterating
    double robustThreshold = 2.0; //!< in sigmas
    int maxIterations = 100;
    int threads = 2;              //!< for the solver's linear algebra; 0 = 1
    bool computeCovariance = true;
    //! Convergence: relative change of the cost, gradient (max norm) and parameters (Ceres' tolerances).
    double functionTolerance = 1e-12;
    double gradientTolerance = 1e-12;
    double parameterTolerance = 1e-12;
    /**
     * Blocks of up to this many images are solved with the dense Schur
     * complement (the reduced camera system as a dense matrix), larger ones
     * with the sparse one.
     */
    int denseSchurMaxImages = 200;
    /**
     * Told after every iteration of the solve (the iterations done of
     * maxIterations; "iteration N, cost C", 0 = the start) and asked there
     * whether to stop: a stop ends the adjustment with Status::Cancelled.
     */
    Progress progress;

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct BundlePointResult
  {
    std::string id;
    Eigen::Vector3d world = Eigen::Vector3d::Zero();
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    int imageCount = 0;
    double rmsPx = 0.0;
    enum class Role
    {
      Tie,
      Control,
      Check
    } role = Role::Tie;
    Eigen::Vector3d errorM = Eigen::Vector3d::Zero(); //!< adjusted - known (control and check points)
  };

  struct BundleImageResult
  {
    std::string id;
    ExteriorOrientation exterior; //!< adjusted, sigma from the adjustment
    int observationCount = 0;
    double rmsPx = 0.0;
    Eigen::Vector3d shiftM = Eigen::Vector3d::Zero(); //!< adjusted - start projection centre
  };

  //! One image observation after the adjustment.
  struct BundleObservationResult
  {
    std::string pointId;
    std::string imageId;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< as measured
    Eigen::Vector2d residualPx = Eigen::Vector2d::Zero();   //!< the adjusted point projected through the adjusted image - measured, pixels
  };

  struct BundleCameraResult
  {
    Camera camera; //!< adjusted interior
    std::vector<std::string> freeParameters;
    std::vector<double> sigmas; //!< of the free parameters, in order
  };

  struct BundleSummary
  {
    enum class Status
    {
      Ok,
      NoDatum,           //!< neither enough control nor pose priors fix the block in space
      TooFewObservations,
      NotConverged,
      Failed,
      Cancelled,         //!< the caller asked to stop (BundleOptions::progress)
    };
    Status status = Status::Ok;
    std::string message;

    std::vector<BundleImageResult> images;
    std::vector<BundleCameraResult> cameras;
    std::vector<BundlePointResult> points;
    std::vector<BundleObservationResult> observations; //!< of the points adjusted, point by point
    std::vector<std::string> skippedPoints; //!< tie or check points seen in fewer than two images
    double sigma0 = 0.0;
    long redundancy = 0;
    int iterations = 0;
    bool converged = false;
    double rmsPx = 0.0;
    Eigen::Vector3d rmseControlM = Eigen::Vector3d::Zero();
    Eigen::Vector3d rmseCheckM = Eigen::Vector3d::Zero();
    int controlCount = 0;
    int checkCount = 0;
    double solveSeconds = 0.0;

    bool ok() const { return status == Status::Ok; }
  };

  /**
   * Adjusts a block. Images must have start orientations; observations of
   * images not listed are refused (std::invalid_argument), as are invalid
   * cameras and non-positive sigmas. Expected failures come back in status.
   */
  BundleSummary bundleAdjust( const std::vector<Camera> &cameras, const std::vector<BundleImage> &images, const std::vector<ControlPoint> &groundPoints,
                              const std::vector<BundleObservation> &observations, const BundleOptions &options = BundleOptions() );

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_BUNDLEADJUSTMENT_H
