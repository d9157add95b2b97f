/***************************************************************************
  degradation.h - camera and transmission faults for simulated images
  -------------------------------------------------------------------------
  Applied to a rendered linear RGB image, in this order: exposure (gain),
  vignetting, Gaussian blur, Gaussian noise, 8-bit quantisation, salt-and-
  pepper bit errors, JPEG compression. All off by default; a seed makes
  the result repeatable.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_DEGRADATION_H
#define GEOSTATION_SIMULATION_DEGRADATION_H

#include <cstdint>

#include <opencv2/core.hpp>

namespace geostation
{

  struct DegradationOptions
  {
    double exposure = 1.0;        //!< gain: < 1 under-, > 1 over-exposed (clipped at 255)
    double vignetting = 0.0;      //!< relative fall-off at the frame corner, 0..1
    double blurSigmaPx = 0.0;     //!< Gaussian blur, pixels
    double noiseSigma = 0.0;      //!< Gaussian noise, grey levels (of 255)
    double bitErrorRate = 0.0;    //!< fraction of pixels set to 0 or 255 (salt and pepper)
    int jpegQuality = 0;          //!< 1..100 to pass the image through JPEG, 0 = off

    //! Throws std::invalid_argument naming the first value out of range.
    void validate() const;
  };

  /**
   * Converts linear RGB (CV_32FC3, 1.0 = white in full sun) to 8-bit RGB
   * (CV_8UC3) with the degradations applied.
   */
  cv::Mat degradeAndQuantise( const cv::Mat &linearRgb, const DegradationOptions &options, uint32_t seed );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_DEGRADATION_H
