/***************************************************************************
  linetrace.h - what every road-line follower shares (thesis ch. 6)
  -------------------------------------------------------------------------
  A road line in an image is either a painted stripe (a bright or dark
  band a few pixels wide: lane markings, centre lines) or an edge (a step
  between two surfaces: asphalt to kerb, kerb to verge). Its LineProfile,
  measured at the seed, tells a follower what to look for; a follower is
  given a start on the line and a direction and returns the sub-pixel
  points it followed and why it stopped.

  Directions are unit vectors in pixel space (col right, row down); an
  angle in degrees is measured from "up the image", clockwise (docs/conventions.md
  §8, trace_road_lines' direction_deg).
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_LINETRACE_H
#define GEOSTATION_TRACING_LINETRACE_H

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  enum class LineKind
  {
    BrightStripe, //!< a painted marking on darker asphalt
    DarkStripe,   //!< a dark band (a crack, a tar seam)
    Edge,         //!< a step between two surfaces
  };

  //! "bright_stripe", "dark_stripe", "edge"
  std::string lineKindName( LineKind kind );

  struct LineProfile
  {
    LineKind kind = LineKind::BrightStripe;
    int polarity = 1;       //!< Edge: +1 when the right-hand side (of the direction of travel) is brighter
    double widthPx = 3.0;   //!< stripe width (full width at half contrast), pixels
    double contrast = 0.0;  //!< stripe: peak above the background; edge: step height; grey levels
  };

  enum class TraceMethod
  {
    Auto,
    Directional,  //!< directional matrices on the thinned edge image (§6.3.1)
    LeastSquares, //!< horizontal-shift least-squares following (§6.3.2)
    Polynomial,   //!< second-order polynomial strips (§6.3.3)
  };

  /**
   * The methods auto tries for a line of this profile, first choice first.
   * Bright stripes (paint): polynomial strips (they bridge dashes, wear and
   * shadows and are the most precise), then the skeleton. Edges and dark
   * bands (a kerb, a kerb's face, a seam): least squares (it matches the
   * seed's profile and stops where the line ends; the strips slide onto a
   * same-polarity edge beside a weak kerb, and onto the seams of cobbles
   * beyond a kerb's end), then the strips, then the skeleton.
   */
  std::vector<TraceMethod> autoMethodOrder( const LineProfile &profile );

  //! "auto", "directional", "least_squares", "polynomial"
  std::string traceMethodName( TraceMethod method );
  //! Throws std::invalid_argument naming the methods.
  TraceMethod traceMethodFromName( const std::string &name );

  //! Why following stopped.
  enum class TraceStop
  {
    EndOfLine,       //!< nothing that looks like the line ahead
    GapTooLarge,     //!< traces of the line ahead, but no continuation within the gap limit
    DirectionChange, //!< the line turns more than the limit allows
    LeftImage,       //!< the line leaves the image(s)
    DistanceLimit,   //!< too far from the cameras for the accuracy wanted (hands over to the next station)
    EndOfRun,        //!< no further station
    MaxStations,     //!< the number of stations asked for is traced
    Cancelled,
    NoEdge,          //!< nothing to follow near the seed or the handover point
    NoStereoPartner, //!< no other image of the station sees the line
    ImageMissing,    //!< an image of the run cannot be read
    StationsOutOfOrder, //!< the next station in time is not ahead along the line
  };

  //! "end_of_line", "gap_too_large", ... (the stop_reason field)
  std::string traceStopName( TraceStop stop );

  //! Degrees from up the image, clockwise -> unit direction (col, row).
  Eigen::Vector2d directionFromDegrees( double degrees );
  double degreesFromDirection( const Eigen::Vector2d &direction );

  //! The right-hand normal of a direction of travel in pixel space (row down).
  inline Eigen::Vector2d rightNormal( const Eigen::Vector2d &direction ) { return Eigen::Vector2d( -direction.y(), direction.x() ); }

  //! Bilinear grey value of an 8-bit image at a continuous pixel position (centres at i + 0.5); nothing outside.
  std::optional<double> sampleGrey( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage );

  struct FollowRequest
  {
    Eigen::Vector2d start = Eigen::Vector2d::Zero(); //!< on the line
    Eigen::Vector2d direction = Eigen::Vector2d( 0, -1 );
    LineProfile profile;
    /**
     * False for a pixel beyond the distance limit (e.g. its road-plane point
     * is too far from the camera): following stops there with DistanceLimit.
     */
    std::function<bool( const Eigen::Vector2d & )> withinLimit;
    int maxSteps = 20000; //!< safety bound
  };

  struct FollowResult
  {
    std::vector<Eigen::Vector2d> points; //!< sub-pixel positions on the line, in order of travel
    std::vector<double> sigmaPx;         //!< across the line, per point
    std::vector<bool> bridged;           //!< per point: the segment that ends here crosses a gap (nothing observed on it); empty = none
    TraceStop stop = TraceStop::EndOfLine;
    int pixelsFollowed = 0;              //!< pixel steps taken along the line
    LineProfile profile;                 //!< as last seen (stripes narrow with distance)
    Eigen::Vector2d direction = Eigen::Vector2d( 0, -1 ); //!< at the end
  };

  //! Options every follower shares.
  struct FollowOptions
  {
    double maxDirectionChangeDeg = 30.0; //!< per direction update (thesis: "too large a difference")
    double directionUpdatePx = 20.0;     //!< Xin's (1995) 20-pixel direction counting distance
    double minContrastFraction = 0.35;   //!< line support: at least this fraction of the seed's contrast
    double minContrastGrey = 6.0;        //!< and at least this many grey levels
  };

  /**
   * `forward` preceded by `backward` (followed the other way from the same
   * start) reversed: one line in forward order, sigmas and bridged flags
   * carried along. Where the two do not meet (the start lay in a gap and
   * both began at the line beyond it), the segment joining them is bridged.
   */
  void joinBackward( const FollowResult &backward, FollowResult &forward );

} // namespace geostation

#endif // GEOSTATION_TRACING_LINETRACE_H
