/***************************************************************************
  pairmapping.h - from one image of a stereo pair to the other (report §4.3)
  -------------------------------------------------------------------------
  The verification needs the lines of one image where they should be in
  the partner, within about 12 px. Three mappings:
  - OrientedPairMapping (the default for an oriented pair): the ray of the
    pixel meets the terrain (a DEM, or a mean terrain height) and the
    ground point is projected into the partner; its error is the parallax
    of the terrain's height error.
  - ProjectiveMapping (eqs. 4-5, 4-6) from at least 4 control-point pairs
    (least squares beyond 4), exact only for a plane.
  - MultiquadricMapping (eqs. 4-7 to 4-14): a translation from the first
    pair plus multiquadric interpolation through all pairs, with the
    smoothing factor SF = c min |P_i - P_k|^2.
  The fitted mappings report their misregistration at the control points
  (the projective's residuals; the multiquadric, which passes through its
  points, leave-one-out residuals). Pixels are pixelInImage (docs/conventions.md §1).
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_PAIRMAPPING_H
#define GEOSTATION_EXTRACTION_PAIRMAPPING_H

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/projection.h"

namespace geostation
{

  class PairMapping
  {
    public:
      virtual ~PairMapping() = default;
      //! Image A -> image B; nothing where the mapping is undefined.
      virtual std::optional<Eigen::Vector2d> toB( const Eigen::Vector2d &pixelInA ) const = 0;
      //! Image B -> image A.
      virtual std::optional<Eigen::Vector2d> toA( const Eigen::Vector2d &pixelInB ) const = 0;
      //! "orientation", "projective", "multiquadric"
      virtual std::string name() const = 0;
  };

  struct ControlPair
  {
    std::string id;
    Eigen::Vector2d inA = Eigen::Vector2d::Zero();
    Eigen::Vector2d inB = Eigen::Vector2d::Zero();
  };

  //! The misregistration of a fitted mapping at its control points (pixels in B).
  struct RegistrationReport
  {
    std::string method;
    std::vector<double> residualsPx; //!< per pair, in input order
    double rmsPx = 0.0;
    double maxPx = 0.0;
    //! The misregistration to expect away from the control points: the projective's largest residual scaled by
    //! sqrt(2n / (2n - 8)) for its redundancy, the multiquadric's largest leave-one-out residual; NaN where the
    //! points cannot tell (4 projective pairs, fewer than 4 multiquadric).
    double expectedPx = std::numeric_limits<double>::quiet_NaN();
  };

  class ProjectiveMapping : public PairMapping
  {
    public:
      /**
       * Fits B from A (least squares beyond 4 pairs). Throws
       * std::invalid_argument with fewer than 4 pairs or collinear points.
       */
      static ProjectiveMapping fit( const std::vector<ControlPair> &pairs, RegistrationReport *report = nullptr );

      std::optional<Eigen::Vector2d> toB( const Eigen::Vector2d &pixelInA ) const override;
      std::optional<Eigen::Vector2d> toA( const Eigen::Vector2d &pixelInB ) const override;
      std::string name() const override { return "projective"; }

    private:
      Eigen::Matrix3d mBFromA = Eigen::Matrix3d::Identity(), mAFromB = Eigen::Matrix3d::Identity();
  };

  class MultiquadricMapping : public PairMapping
  {
    public:
      /**
       * Fits both directions through the pairs. Throws std::invalid_argument
       * with fewer than 3 pairs, repeated points, or collinear points.
       * `smoothing` is c of SF = c min |P_i - P_k|^2.
       */
      static MultiquadricMapping fit( const std::vector<ControlPair> &pairs, double smoothing = 1.0, RegistrationReport *report = nullptr );

      std::optional<Eigen::Vector2d> toB( const Eigen::Vector2d &pixelInA ) const override;
      std::optional<Eigen::Vector2d> toA( const Eigen::Vector2d &pixelInB ) const override;
      std::string name() const override { return "multiquadric"; }

      //! One direction: u = x - (x0 - u0) + sum a_k sqrt(|x - x_k|^2 + SF).
      struct Surface
      {
        std::vector<Eigen::Vector2d> nodes;
        Eigen::Vector2d shift = Eigen::Vector2d::Zero(); //!< u0 - x0, v0 - y0
        Eigen::MatrixX2d coefficients;                    //!< a_k, b_k
        double sf = 0.0;
        Eigen::Vector2d apply( const Eigen::Vector2d &p ) const;
      };

    private:
      Surface mForward, mBackward;
  };

  //! Height of the terrain at (x, y) in the block CRS; nothing where unknown.
  using TerrainHeight = std::function<std::optional<double>( double x, double y )>;

  class OrientedPairMapping : public PairMapping
  {
    public:
      /**
       * `terrain` may be empty (the mean height is used everywhere); where it
       * has no height, the mean height is used.
       */
      OrientedPairMapping( const OrientedImage &a, const OrientedImage &b, double meanHeightM, TerrainHeight terrain = nullptr );

      std::optional<Eigen::Vector2d> toB( const Eigen::Vector2d &pixelInA ) const override;
      std::optional<Eigen::Vector2d> toA( const Eigen::Vector2d &pixelInB ) const override;
      std::string name() const override { return "orientation"; }

      //! The ground point of a pixel of one image (ray and terrain), or nothing.
      std::optional<Eigen::Vector3d> groundPoint( const OrientedImage &image, const Eigen::Vector2d &pixelInImage ) const;

      const OrientedImage &imageA() const { return mA; }
      const OrientedImage &imageB() const { return mB; }
      double meanHeightM() const { return mMeanHeightM; }

    private:
      OrientedImage mA, mB;
      double mMeanHeightM;
      TerrainHeight mTerrain;
  };

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_PAIRMAPPING_H
