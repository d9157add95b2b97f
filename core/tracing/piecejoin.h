/***************************************************************************
  piecejoin.h - one line from the pieces traced from several seeds
  -------------------------------------------------------------------------
  A long run is traced in pieces: seeds of one line at different stations,
  each traced up to the next seed's station and some stations beyond. The
  pieces of a line, in the order of their seeds, are joined into one. A
  trace needs some stations to settle, and its last stations are its least
  settled: where the two pieces run together in their overlap (within
  `agreeM` for `agreeVertices` vertices or more), the earlier piece is kept
  up to the last place they do and the later one goes on from there. Where
  they never do, the later one goes on from its start, and a vertex of the
  earlier one beyond it farther off than `sigmaFactor` times their combined
  sigma is reported (the two traces disagree: one of them has left the
  line). A piece that ends before the next one starts leaves a gap, joined
  straight and reported.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_PIECEJOIN_H
#define GEOSTATION_TRACING_PIECEJOIN_H

#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  //! One traced piece of a line.
  struct TracedPiece
  {
    std::string lineId;
    int order = 0;                       //!< along the line: its seed's place among the line's seeds
    std::vector<Eigen::Vector3d> points; //!< block CRS
    double sigmaM = 0.0;                 //!< its largest vertex sigma
    std::string name;                    //!< to name it in a report (e.g. its seed id)
  };

  struct PieceJoinOptions
  {
    double sigmaFactor = 3.0;    //!< a vertex farther off than this many combined sigmas disagrees
    double minToleranceM = 0.01; //!< the tolerance's floor
    double agreeM = 0.01;        //!< two pieces run together where their vertices are this close
    int agreeVertices = 5;       //!< ... for at least this many vertices in a row
    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  //! Two consecutive pieces of a line that do not agree where they overlap, or do not meet.
  struct PieceDisagreement
  {
    std::string lineId, first, second; //!< the pieces' names
    double worstM = 0.0;                //!< the farthest vertex of the first from the second (3-D), or the gap
    double allowedM = 0.0;              //!< sigmaFactor x the combined sigma
    double overlapM = 0.0;              //!< the length of the first beyond where the second starts (XY); 0 for a gap
    bool gap = false;                   //!< the first ends before the second starts
  };

  struct JoinedLine
  {
    std::string lineId;
    std::vector<Eigen::Vector3d> points;
    double sigmaM = 0.0;
    int pieces = 0;
  };

  struct PieceJoinSummary
  {
    std::vector<JoinedLine> lines; //!< by line id
    std::vector<PieceDisagreement> disagreements;
  };

  /**
   * The pieces joined per line id (see the file comment). Throws
   * std::invalid_argument for bad options or two pieces of one line with
   * the same order; a piece of fewer than two points is left out.
   */
  PieceJoinSummary joinTracedPieces( const std::vector<TracedPiece> &pieces, const PieceJoinOptions &options = PieceJoinOptions() );

} // namespace geostation

#endif // GEOSTATION_TRACING_PIECEJOIN_H
