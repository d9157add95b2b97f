/***************************************************************************
  photoidentification.h - control identified in a photo file, end to end
  -------------------------------------------------------------------------
  What geostation:identify_control and the orientation dock's "Identify"
  share: the marks of the photo's file (scan pixels for a scanned film)
  detected and taken into the camera's nominal frame, the distance-list
  identification (controlidentification.h), and each identified mark
  located again at its prediction from the identified orientation (the
  semi-automatic step, controlprediction.h) at the size the marks have on
  the ground: what that finds is measured there (control points the
  distance lists missed included). A mark is claimed only within
  agreementPx of its prediction by the final orientation (good to a fraction
  of a pixel) and within three times the marks' median residual; one
  further off is flagged for the operator.
  Pixels in and out are the file's.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_PHOTOIDENTIFICATION_H
#define GEOSTATION_IDENTIFICATION_PHOTOIDENTIFICATION_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "identification/controlidentification.h"
#include "identification/controlprediction.h"
#include "identification/markcandidates.h"

namespace geostation
{

  struct PhotoIdentificationOptions
  {
    MarkCandidateOptions marks;
    ControlIdentificationOptions identification;
    //! A mark is claimed only within this of its prediction by the final orientation (pixels), and within three times the
    //! found marks' median residual (at least 0.5 px); further off it is flagged.
    double agreementPx = 1.0;
    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  //! One identified control point, in the file's pixels.
  struct PhotoIdentifiedPoint
  {
    std::string pointId;
    Eigen::Vector2d pixelInFile = Eigen::Vector2d::Zero();
    Eigen::Vector2d predictedInFile = Eigen::Vector2d::Zero(); //!< by the identified orientation
    double sigmaPx = 0.5;
    bool relocated = false;  //!< measured at its prediction by the second pass (else the detected mark's centre)
  };

  struct PhotoIdentificationSummary
  {
    ControlIdentificationSummary identification; //!< the search, its status and message, the resection
    std::vector<PhotoIdentifiedPoint> identified;
    std::vector<std::pair<std::string, Eigen::Vector2d>> notFound; //!< predicted in the photo (file pixels), no mark paired
    //! a mark at or paired with a control point, further than agreementPx from its prediction: for the operator, not claimed
    std::vector<PhotoIdentifiedPoint> flagged;
    int candidates = 0;
    int relocated = 0;         //!< measured at their prediction by the second pass
    int addedAtPrediction = 0; //!< of those, control points the distance lists had not paired
    int unclaimed = 0;         //!< paired or found, but further than claimLimitPx from the final prediction (flagged)
    double claimLimitPx = 0.0; //!< agreementPx, or less: three times the found marks' median residual (at least 0.5 px)
    bool ok() const { return identification.ok(); }
  };

  /**
   * Identifies `control` in the photo `greyFile` (8-bit grey, the file's
   * pixels; markGrey()). `nominalFromFile` is a scanned film's scan affine.
   * Throws like identifyControl().
   */
  PhotoIdentificationSummary identifyControlInPhoto( const cv::Mat &greyFile, const Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile,
      const std::vector<ControlPoint> &control, const PhotoIdentificationOptions &options = PhotoIdentificationOptions() );

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_PHOTOIDENTIFICATION_H
