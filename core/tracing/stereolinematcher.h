/***************************************************************************
  stereolinematcher.h - a traced line found in the stereo partner, in 3-D
  -------------------------------------------------------------------------
  Thesis §6.5.1-6.5.2. The start point's ground position is predicted from
  the road plane (the plane Z = mean of the two cameras' Z minus their
  height above the road, eqs. 6.22-6.25) or from a DEM; projected into the
  partner it gives the search position on the start's epipolar curve.
  There the start is refined by correlation over about 15 px along the
  curve, with a window extended along the line (21 x 7 px), both windows
  sampled along the line's direction in their own image so they show
  like-shaped patches. The line is then followed in the partner with the
  same method, and each interval point of the reference line finds its
  conjugate where its epipolar curve (restricted to a short depth range
  around the prediction) crosses the partner's line. The two rays are
  intersected with standard deviations; the station's GNSS/INS sigmas are
  propagated too, since both cameras move with the van.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_STEREOLINEMATCHER_H
#define GEOSTATION_TRACING_STEREOLINEMATCHER_H

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/projection.h"
#include "geometry/windowshape.h"
#include "tracing/linetrace.h"

namespace geostation
{
  struct LineRelocation;

  struct StereoImage
  {
    std::string imageId;
    const OrientedImage *image = nullptr;
    const cv::Mat *grey = nullptr;
  };

  struct StartMatch
  {
    enum class Status
    {
      Ok,
      NoGround,         //!< the start's ray does not reach the road surface
      NotInView,        //!< the partner does not see the start
      NoEpipolarCurve,  //!< the start's epipolar curve does not reach the partner
      AtBorder,         //!< the start is too close to the reference image's border for a window
      NotFound,         //!< no window along the epipolar curve correlates well enough
      AtSearchEnd,      //!< the best correlation lies at the end of the search: the line may be beyond it
    };
    Status status = Status::NotFound;
    std::string message; //!< one sentence when not ok
    bool ok() const { return status == Status::Ok; }
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< in the partner
    Eigen::Vector2d direction = Eigen::Vector2d( 0, -1 );   //!< the line's direction there
    double score = 0.0;                                     //!< NCC of the best window
  };

  struct StartMatchOptions
  {
    double searchAlongCurvePx = 7.5; //!< each side of the prediction (~15 px in all), at least
    double heightToleranceM = 0.3;   //!< and as far as the road surface may lie above or below the predicted ground
    int windowAlongPx = 21;   //!< at least; three times the window's width
    int windowAcrossPx = 7;   //!< at least; a stripe's window is 2.5 x its width + 4, so it shows the asphalt either side
    double minScore = 0.6;
  };

  /**
   * The reference line's start (pixel and direction in the reference) in
   * the partner image: prediction from `groundOfPixel`, then correlation
   * along the epipolar curve. The window follows the surface into the
   * partner: each template sample's ray meets the surface, moved up or
   * down to pass through the candidate's point on the start's ray (within
   * heightToleranceM), and is projected into the partner, so a partner
   * that sees the road at another scale or shear still correlates. Where a
   * sample's ray misses the surface the window is the reference's shape
   * turned to the line's predicted direction.
   */
  StartMatch matchStartInPartner( const StereoImage &reference, const Eigen::Vector2d &pixelInReference, const Eigen::Vector2d &directionInReference,
                                  const StereoImage &partner, const GroundOfPixel &groundOfPixel, const LineProfile &profile,
                                  const StartMatchOptions &options = StartMatchOptions() );

  struct LineVertex3d
  {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();          //!< block CRS, metres
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();     //!< m^2: pixels and, if asked, the station's pose
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    Eigen::Vector2d pixelInReference = Eigen::Vector2d::Zero();
    Eigen::Vector2d pixelInPartner = Eigen::Vector2d::Zero();
    Eigen::Vector2d residualReferencePx = Eigen::Vector2d::Zero(), residualPartnerPx = Eigen::Vector2d::Zero();
    double rangeM = 0.0;                                      //!< from the reference camera
    double sigmaReferencePx = 0.0;    //!< of the reference point (col and row)
    double sigmaPartnerLinePx = 0.0;  //!< of the partner's line, across it
    Eigen::Vector2d partnerLineDirection = Eigen::Vector2d( 0, -1 ); //!< the partner's line at the conjugate (unit)
    //! The line seen at this vertex in other stations' images (refineFromOtherStations()).
    struct OtherObservation
    {
      std::string imageId;
      Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< on the line
      Eigen::Vector2d residualPx = Eigen::Vector2d::Zero();   //!< projected - observed, across the line
    };
    std::vector<OtherObservation> others;
  };

  struct VertexMatchOptions
  {
    double heightToleranceM = 0.3;   //!< the epipolar curve where the ray is within this height of the predicted road surface
    double minCrossingSine = 0.1;    //!< epipolar curve and partner line closer to parallel: no vertex
    double maxPartnerSigmaPx = 2.0;
    double pixelSigmaFloorPx = 0.15;
    /**
     * The line's own uncertainty across it on the road (m; 0: none): paint
     * worn unevenly or ragged edges put a stripe's centre off its line by
     * about the same distance on the road whatever the range, so each
     * image's observation gets at least this, in its own pixels
     * (pixelsPerMetreAcross()).
     */
    double lineSigmaM = 0.0;
    bool propagateExterior = true;   //!< add the station's GNSS/INS sigmas (the reference image's)
  };

  /**
   * How far (px) the image of a road line moves across itself when the line
   * moves one metre sideways on the road, at `ground` with the line running
   * along `alongGround` there. 0 where either does not project.
   */
  double pixelsPerMetreAcross( const OrientedImage &image, const Eigen::Vector3d &ground, const Eigen::Vector3d &alongGround );

  /**
   * 3-D vertices of the reference line's interval points: each one's
   * epipolar curve crossed with the partner's line (pixels and sigmas), then
   * intersected. Points whose conjugate cannot be found are left out.
   * With `partnerRelocation`, the partner's line is located again across
   * each conjugate (relocateOnLine(), the same length of line on the
   * ground as the reference points were put on) and the conjugate moves
   * along its epipolar curve onto it.
   */
  std::vector<LineVertex3d> intersectLineVertices( const StereoImage &reference, const std::vector<Eigen::Vector2d> &referencePoints, const std::vector<double> &referenceSigmaPx,
      const StereoImage &partner, const FollowResult &partnerLine, const GroundOfPixel &groundOfPixel, const VertexMatchOptions &options = VertexMatchOptions(),
      const LineRelocation *partnerRelocation = nullptr );

  /**
   * Covariance (m^2) of a ground point from a rig's GNSS/INS sigmas: the
   * rig shifted and turned by small angles about `rigCentre`, so every
   * point the rig measures moves with it. Zero without sigmas.
   */
  Eigen::Matrix3d rigPoseCovariance( const ExteriorOrientation &exterior, const Eigen::Vector3d &point, const Eigen::Vector3d &rigCentre );

  /**
   * Points along a followed line every `spacingPx` (and its vertices), each
   * with the sigma of the nearer vertex; none inside bridged gaps, where
   * nothing was observed.
   */
  void intervalPoints( const FollowResult &line, double spacingPx, std::vector<Eigen::Vector2d> &points, std::vector<double> &sigmas );

} // namespace geostation

#endif // GEOSTATION_TRACING_STEREOLINEMATCHER_H
