/***************************************************************************
  polygoncompilation.h - maximum-length polygons of a result matrix (§4.2)
  -------------------------------------------------------------------------
  Follows the strings of chosen symbols: 3 x 3 neighbourhoods tell a dead
  end (one neighbour), the line's run (two) and an intersection (more);
  the pixels of an intersection are examined together (Kazmierczak et al.'s (1983) 5 x 5
  crossing examination) so that its branches leave from one node, placed
  where the branches' lines meet. A node only one line leaves is the blob
  at a line's end (a dead end); a node two lines leave is a bend of one
  line. Each polygon runs between two dead ends, two intersections, or one
  of each, without an intersection inside.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_POLYGONCOMPILATION_H
#define GEOSTATION_EXTRACTION_POLYGONCOMPILATION_H

#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  class ResultMatrix;

  //! How a compiled polygon ends.
  enum class PolygonEnd
  {
    DeadEnd,
    Intersection,
  };

  struct CompiledPolygon
  {
    std::vector<Eigen::Vector2d> pixels; //!< vertices through the pixel centres (Douglas-Peucker, 0.75 px), ends included (an intersection's end at its centre)
    PolygonEnd startEnd = PolygonEnd::DeadEnd, endEnd = PolygonEnd::DeadEnd;
    std::string symbols; //!< the distinct symbols along it, in order of first appearance (e.g. "I", "IE")
  };

  struct CompilationSummary
  {
    std::vector<CompiledPolygon> polygons;
    std::vector<Eigen::Vector2d> intersections; //!< centres of the intersections (pixelInImage)
  };

  /**
   * Maximum-length polygons of the strings of `symbols` in the matrix;
   * polygons shorter than `minPixels` pixels are dropped (stubs). With
   * `erase`, the compiled symbols are cleared from the matrix.
   */
  CompilationSummary compileMaxLengthPolygons( ResultMatrix &matrix, const std::string &symbols, bool erase, int minPixels = 3 );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_POLYGONCOMPILATION_H
