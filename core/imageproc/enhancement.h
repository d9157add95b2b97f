/***************************************************************************
  enhancement.h - image enhancement for viewing and matching (thesis ch. 4, §6.1)
  -------------------------------------------------------------------------
  Grey-level transformations:
    equalise           histogram equalisation (eqs. 4.1-4.4)
    linear             linear stretch of [min, max] to [outLow, outHigh] (eq. 4.5)
    two_segment        two segments split at the mean, the mean moved to
                       preferredMean (eqs. 4.6a-b)
    three_segment      Xin's (1995) adaptive stretch (eqs. 4.7a-c): a = mean,
                       b = mean + 30, a' = 150 by default
  Sharpening by "add-back":
    sobel_addback      e += scale * G, G the largest of the Sobel gradients in
                       x, y and the two diagonals of the extended neighbourhood
                       (eqs. 4.10-4.14), where |G| > threshold
    difference_addback e += scale * max(e - neighbour) over the 8 neighbours
                       (eqs. 4.15-4.16), where it exceeds the threshold
  Noise:
    box_filter         the adaptive box filter for bit errors (Eliason and
                       McEwen; eqs. 6.1-6.8): a pixel further than C sigma and
                       T from its box mean is replaced by the mean of the
                       others
  8- and 16-bit, grey or RGB (grey-level mappings are computed on the
  luminance and applied to every band alike, so colours keep their hue;
  filters work band by band), on the whole image or in a window (the
  statistics and the change stay inside it). Levels scale with the type:
  Xin's (1995) 255, 30 and 150 become 65535, 7710 and 38550 for 16 bits.
 ***************************************************************************/
#ifndef GEOSTATION_IMAGEPROC_ENHANCEMENT_H
#define GEOSTATION_IMAGEPROC_ENHANCEMENT_H

#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace geostation
{

  enum class EnhancementMethod
  {
    Equalise,
    LinearStretch,
    TwoSegmentStretch,
    ThreeSegmentStretch,
    SobelAddBack,
    DifferenceAddBack,
    AdaptiveBoxFilter,
  };

  std::string enhancementMethodName( EnhancementMethod method );
  //! equalise, linear, two_segment, three_segment, sobel_addback, difference_addback, box_filter
  std::optional<EnhancementMethod> enhancementMethodFromName( const std::string &name );

  //! Levels are on the 8-bit scale; they are scaled for 16-bit images.
  struct EnhancementOptions
  {
    EnhancementMethod method = EnhancementMethod::ThreeSegmentStretch;
    double outLow = 0.0, outHigh = 255.0;   //!< linear: the target range (a, b of eq. 4.5)
    double clipPercent = 0.0;               //!< linear: ignore this % at each end when finding min and max
    double preferredMean = 128.0;           //!< two_segment: pmean
    double threeSegmentWidth = 30.0;        //!< three_segment: b - a
    double threeSegmentTarget = 150.0;      //!< three_segment: a'
    double scale = 0.5;                     //!< add-back: 0 < scale < 1 (0.3-0.7 usual)
    double threshold = 20.0;                //!< add-back: gradient or difference threshold
    int boxHalfWidth = 2, boxHalfHeight = 2; //!< box filter: a (2k+1) x (2m+1) box
    double boxC = 1.5;                      //!< box filter: C, between 1 and 2
    double boxT = 10.0;                     //!< box filter: T, the minimum difference
    std::optional<cv::Rect> window;         //!< only this part of the image (clipped to it)

    //! Throws std::invalid_argument naming the first value out of range.
    void validate() const;
  };

  struct EnhancementSummary
  {
    double mean = 0.0, min = 0.0, max = 0.0; //!< luminance statistics used (window or image)
    long changedPixels = 0;                   //!< add-back and box filter: pixels altered
  };

  /**
   * The enhanced image, of the input's type and size. Throws
   * std::invalid_argument for an image that is not 8- or 16-bit with 1 or 3
   * bands, or a window outside the image.
   */
  cv::Mat enhanceImage( const cv::Mat &image, const EnhancementOptions &options, EnhancementSummary *summary = nullptr );

} // namespace geostation

#endif // GEOSTATION_IMAGEPROC_ENHANCEMENT_H
