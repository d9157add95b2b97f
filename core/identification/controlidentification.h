/***************************************************************************
  controlidentification.h - which image point is which control point
  -------------------------------------------------------------------------
  Automatic identification of ground control in one photo (the monoplotter
  paper, §5, its proposal of "ordered distances between all possible point
  pairs", finished here for any viewing direction):

    * Hypotheses from triangles. Each control point with two of its nearest
      neighbours on the ground (Stokes' (1988) distance list, taken locally)
      is paired with each candidate and two of its nearest candidates in
      the image. A pair is kept only when the triangle keeps its sense of
      rotation (a camera above a near-horizontal triangle cannot mirror it)
      and the side lengths' scales agree within the foreshortening allowed.
    * Each kept pairing is solved exactly for the camera's pose from three
      rays (P3P, the interior orientation known) - heights are part of the
      solution, where Stokes (1988) corrected its distances for them - and
      scored by the number of other control points it projects onto a
      candidate.
    * The best distinct hypotheses are verified by the space resection
      (resection.h): robust, with blunders removed, all control projected
      again and matched within a tight tolerance until the set is stable.
      A solution counts only when chance cannot explain it (a contrario):
      the number of poses tried times the probability that as many control
      points fall on candidates by chance, from the candidates' density
      around each predicted point, must stay below maxFalseAlarms. A pose
      chosen among hundreds of thousands lines a handful of points up with
      dense texture or a row of marks along a road; the test removes those.
      The one with most pairs wins; it must beat the runner-up clearly,
      otherwise the result is ambiguous and nothing is claimed.

  With an approximate orientation (a previous resection, GNSS/INS, a
  camera position and height) each control point is paired only with the
  candidates near its prediction, which is faster and can tell apart
  patterns the geometry alone cannot.

  Candidates and results are pixels of the camera's nominal frame
  (docs/conventions.md §1); a scanned photo's candidates go through its inner
  orientation first.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_CONTROLIDENTIFICATION_H
#define GEOSTATION_IDENTIFICATION_CONTROLIDENTIFICATION_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adjustment/controlpoint.h"
#include "adjustment/resection.h"
#include "camera/camera.h"
#include "progress/progress.h"
#include "geometry/exteriororientation.h"

namespace geostation
{

  struct ControlIdentificationOptions
  {
    int neighboursOnGround = 4;     //!< each control point's nearest, two of them per triangle
    int neighboursInImage = 6;      //!< each candidate's nearest, two of them per triangle
    int candidatesForHypotheses = 30; //!< triangles in the image among the first (strongest) candidates; all count for the score
    double maxForeshortening = 5.0; //!< largest ratio between the scales of a triangle's sides
    double hypothesisTolerancePx = 6.0; //!< control projected this close to a candidate counts for a hypothesis
    double tolerancePx = 2.5;       //!< after the resection: the final matching radius
    int minPairs = 5;               //!< fewer identified pairs is no identification
    //! A solution is accepted when fewer than this many of the poses tried would match as many points by chance.
    double maxFalseAlarms = 0.1;
    double densityRadiusPx = 50.0;  //!< the candidates' density around a predicted point is counted within this radius
    int runnerUpMargin = 2;         //!< the winner must have this many pairs more than a different solution
    int hypothesesVerified = 24;    //!< the best distinct hypotheses verified by resection
    double candidateSigmaPx = 0.5;  //!< σ of a candidate's position, for the resection
    std::optional<ExteriorOrientation> approximate; //!< an approximate orientation, when there is one
    double searchRadiusPx = 80.0;   //!< with `approximate`: candidates this close to a prediction
    ResectionOptions resection;     //!< robust and removeBlunders are set by the identification
    //! Told after each candidate the search takes up and asked there, and before each hypothesis verified, whether to stop (Status::Cancelled)
    Progress progress;

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  //! A control point identified with a candidate.
  struct IdentifiedControl
  {
    std::string pointId;
    int candidate = -1;                      //!< index into the candidates given
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< the candidate's position
    Eigen::Vector2d residualPx = Eigen::Vector2d::Zero();   //!< projected - candidate, from the final resection
  };

  //! A control point the final orientation puts in the frame where no candidate is.
  struct PredictedControl
  {
    std::string pointId;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< predicted
  };

  struct ControlIdentificationSummary
  {
    enum class Status
    {
      Ok,
      TooFewCandidates, //!< fewer than three candidates (or than minPairs)
      TooFewControl,    //!< fewer than minPairs control points (near the approximate orientation)
      NotFound,         //!< no hypothesis survived the resection with minPairs pairs
      Ambiguous,        //!< two different solutions almost equally good
      Cancelled,        //!< the caller asked to stop (ControlIdentificationOptions::progress)
    };
    Status status = Status::NotFound;
    std::string message;
    std::vector<IdentifiedControl> identified;   //!< in the control's order
    std::vector<PredictedControl> notFound;      //!< in the frame, no candidate (hidden, absent or not detected)
    std::vector<std::string> rejected;           //!< paired by the hypothesis, removed by the resection as blunders
    ResectionSummary resection;                  //!< the final resection (valid when ok())
    long triangles = 0;          //!< triangle pairings tried
    long poses = 0;              //!< P3P solutions scored
    int hypothesesVerified = 0;
    int runnerUpPairs = 0;       //!< pairs of the best accepted solution different from the winner
    double falseAlarms = 0.0;    //!< the winner's: poses tried x chance of as many pairs (a contrario)
    double seconds = 0.0;

    bool ok() const { return status == Status::Ok; }
  };

  /**
   * Identifies `control` among `candidatesPx` (pixels, strongest first is
   * best but not needed). Throws std::invalid_argument for an invalid
   * camera, duplicate control ids, non-finite input or bad options;
   * expected failures come back in the summary's status and message.
   */
  ControlIdentificationSummary identifyControl( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<Eigen::Vector2d> &candidatesPx,
      const ControlIdentificationOptions &options = ControlIdentificationOptions() );

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_CONTROLIDENTIFICATION_H
