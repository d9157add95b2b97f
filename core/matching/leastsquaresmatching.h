/***************************************************************************
  leastsquaresmatching.h - Gruen's least-squares matching (thesis §5.1.2)
  -------------------------------------------------------------------------
  The target window around a reference pixel is related to the search image
  by an affine transformation and a linear radiometric one (eq. 5.9):
      g_t(x, y) = h0 + h1 g_s(a0 + a1 x + a2 y, b0 + b1 x + b2 y),
  (x, y) the offsets from the reference pixel. Gauss-Newton on the
  linearised observation equations (eq. 5.10), resampling the search image
  by cubic B-spline interpolation with the spline's own derivatives as
  gradients. (Xin (1995) resamples bilinearly with central-difference
  gradients, eqs. 5.12-5.15; their mismatch stalls the iteration short of
  hundredths of a pixel, and bilinear or Keys resampling bias the shift.)
  until the shift changes by less than a threshold. (a0, b0) is the match.
  Divergent, degenerate or runaway solutions are rejected with a reason.
 ***************************************************************************/
#ifndef GEOSTATION_MATCHING_LEASTSQUARESMATCHING_H
#define GEOSTATION_MATCHING_LEASTSQUARESMATCHING_H

#include <string>

#include <Eigen/Core>

#include "matching/matchimage.h"

namespace geostation
{

  struct LsmOptions
  {
    int windowWidth = 9;          //!< odd; Xin's (1995) best size for general objects is 9 x 9
    int windowHeight = 9;
    int maxIterations = 60;       //!< strong distortion (a 40° viewpoint change) needs about 40 with the shape freed late
    double convergencePx = 1e-3;  //!< stop when the shift changes by less than this
    double maxShiftPx = -1.0;     //!< reject a match this far from the start (default: half the window)
    bool shape = true;            //!< estimate the affine shape (false: shifts and radiometry only)
    //! The shape to start from ([a1 a2; b1 b2]): identity, or one predicted from the geometry (or the inverse of a forward match's).
    Eigen::Matrix2d initialAffine = Eigen::Matrix2d::Identity();
    /**
     * Resampling of the search window: the cubic B-spline (exact at the
     * pixels, smooth derivatives; the default, for the best sub-pixel
     * accuracy) or Xin's (1995) bilinear interpolation (eq. 5.15) with central
     * differences as gradients.
     */
    enum class Resampling
    {
      CubicBSpline,
      Bilinear,
    };
    Resampling resampling = Resampling::CubicBSpline;
    /**
     * Gaussian smoothing (sigma, reference pixels) of the reference window
     * before matching: where the search image shows the patch at a coarser
     * scale, the reference's finer detail has no counterpart there and only
     * spoils the fit. 0: none.
     */
    double referenceBlurPx = 0.0;

    //! Throws std::invalid_argument with one sentence for even or too small windows, no iterations, a non-positive convergence threshold or a negative blur.
    void check() const;
  };

  struct LsmResult
  {
    enum class Status
    {
      NotRun,       //!< least squares was not tried
      Converged,
      Outside,      //!< the window leaves the reference or the search image
      Flat,         //!< no texture, or a line or an edge whose shift along itself the window cannot fix (singular normal equations)
      Diverged,     //!< a runaway, degenerate or non-finite solution, or one that left the search window
      NotConverged, //!< the iterations ran out
    };
    Status status = Status::NotRun;
    std::string message;                               //!< why not, when not converged
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< (a0, b0) in the search image
    Eigen::Vector2d sigmaPx = Eigen::Vector2d::Zero();       //!< standard deviations of a0, b0
    double sigma0 = 0.0;                               //!< grey levels
    int iterations = 0;
    Eigen::Matrix2d affine = Eigen::Matrix2d::Identity(); //!< [a1 a2; b1 b2]
    double h0 = 0.0, h1 = 1.0;

    bool converged() const { return status == Status::Converged; }
    //! A line or an edge, or no texture: LSM is not applicable (the correlation peak stands).
    bool degenerate() const { return status == Status::Flat; }
    double sigmaPxMax() const { return sigmaPx.maxCoeff(); }
  };

  //! "not_run", "converged", "outside", "flat", "diverged", "not_converged"
  std::string lsmStatusName( LsmResult::Status status );

  /**
   * Matches the window around `pixelInReference` into `search`, starting at
   * `approximateInSearch` with options.initialAffine. Expected failures
   * (the window leaves an image, no texture, divergence) are returned in
   * the status; invalid options throw std::invalid_argument (LsmOptions::check()).
   */
  LsmResult leastSquaresMatch( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                               const Eigen::Vector2d &approximateInSearch, const LsmOptions &options = LsmOptions() );

} // namespace geostation

#endif // GEOSTATION_MATCHING_LEASTSQUARESMATCHING_H
