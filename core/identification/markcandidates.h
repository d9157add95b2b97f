/***************************************************************************
  markcandidates.h - candidates for signalised control points in a photo
  -------------------------------------------------------------------------
  The first step of identifying ground control automatically (Stokes
  1988, §5: "identify candidates for ground control points by
  processing the total image using the Förstner interest operator"):

    1. a centre-surround filter (mean of a square minus the mean of the
       ring around it, box filters) over a range of mark sizes finds bright
       (or dark) compact marks, local maxima over position and size; each
       side of the ring must be darker on its own, so a ridge against the
       sky, an edge or a stripe is not a mark;
    2. each is located by the Förstner operator with a window covering the
       mark (the point nearest to all its gradient lines: the centre of a
       disc or of a square), or by its centre of gravity where Förstner
       finds no point there;
    3. the strongest (by contrast) are kept.

  Not every candidate is a control point: roof corners, car roofs, road
  paint and unknown marks come too. The identification (controlidentification.h)
  sorts them out.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_MARKCANDIDATES_H
#define GEOSTATION_IDENTIFICATION_MARKCANDIDATES_H

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  struct MarkCandidateOptions
  {
    double minDiameterPx = 3.0;   //!< smallest mark looked for (the disc, not its background)
    double maxDiameterPx = 0.0;   //!< largest; 0: a tenth of the image's shorter side (at most 200 px)
    double minContrast = 30.0;    //!< grey levels between the mark and the ring around it
    //! Every side of the ring (above, below, left, right) must be darker by this fraction of the contrast.
    double minSideContrast = 0.5;
    bool brightMark = true;       //!< false: dark marks on a bright background
    int maxCandidates = 60;       //!< the strongest kept
    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct MarkCandidate
  {
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< docs/conventions.md §1, sub-pixel
    double contrast = 0.0;     //!< grey levels, mark minus ring (bright marks)
    double diameterPx = 0.0;   //!< the filter size that answered best
    bool forstner = false;     //!< located by Förstner (else by the centre of gravity)
  };

  //! The largest mark looked for in an image of `size`: the options' or, for 0, a tenth of its shorter side (3-200 px).
  double largestMarkPx( const MarkCandidateOptions &options, const cv::Size &size );

  /**
   * Mark candidates of an 8-bit grey image, strongest first. Throws
   * std::invalid_argument for another image type or bad options.
   */
  std::vector<MarkCandidate> detectMarkCandidates( const cv::Mat &grey, const MarkCandidateOptions &options = MarkCandidateOptions() );

  /**
   * The 8-bit grey image marks are looked for in, from a photo as read
   * (8- or 16-bit, grey, RGB or RGBA; 16-bit stretched between its 0.1 and
   * 99.9 percentiles). Throws std::invalid_argument for anything else.
   */
  cv::Mat markGrey( const cv::Mat &image );

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_MARKCANDIDATES_H
