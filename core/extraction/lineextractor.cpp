/***************************************************************************
  lineextractor.cpp - line extraction in one image
 ***************************************************************************/
#include "extraction/lineextractor.h"
#include "extraction/stopwatch.h"

#include <stdexcept>

namespace geostation
{

  void LineExtractionOptions::check() const
  {
    object.check();
    start.check();
    lem.check();
    rem.check();
    if ( subImageSizePx < 64 )
      throw std::invalid_argument( "sub-images must be at least 64 px" );
    if ( minSteps < 1 || maxHandovers < 1 )
      throw std::invalid_argument( "a line needs at least one step and one hand-over" );
  }

  namespace
  {
    struct Piece
    {
      std::vector<Eigen::Vector2d> pixels;
      uint8_t symbol;
    };

    struct FollowResult
    {
      std::vector<Piece> pieces;
      DeadEnd end;
      int lemSteps = 0;
    };

    //! LEM, REM at its break-offs, LEM again where REM finds the line ideal; until a final stop.
    FollowResult follow( const cv::Mat &grey, const ResultMatrix &matrix, const LineState &start, const LineExtractionOptions &options,
                         LineExtractionSummary &summary )
    {
      FollowResult result;
      LineState state = start;
      DeadEndKind stop = DeadEndKind::BreakOff;
      for ( int handover = 0; handover < options.maxHandovers; ++handover )
      {
        Stopwatch t;
        const LemSummary lem = followLocally( grey, matrix, state, options.object, options.lem );
        summary.lemStage.seconds += t.seconds();
        summary.lemStage.linePx += polylineLength( lem.pixels );
        result.lemSteps += lem.steps;
        if ( lem.pixels.size() > 1 )
          result.pieces.push_back( { lem.pixels, ResultMatrix::kLocal } );
        state = lem.end;
        stop = lem.stop;
        if ( stop != DeadEndKind::BreakOff )
          break;
        t.restart();
        const RemSummary rem = followRegionally( grey, matrix, state, options.object, options.lem, options.rem );
        summary.remStage.seconds += t.seconds();
        summary.remStage.linePx += polylineLength( rem.pixels );
        if ( rem.pixels.size() > 1 )
          result.pieces.push_back( { rem.pixels, ResultMatrix::kRegional } );
        state = rem.end;
        stop = rem.stop;
        if ( stop != DeadEndKind::Ideal )
          break;
      }
      if ( stop == DeadEndKind::BreakOff || stop == DeadEndKind::Ideal )
        stop = DeadEndKind::FinalBreakOff;
      result.end = { state, stop };
      return result;
    }

    void draw( ResultMatrix &matrix, const FollowResult &line, LineExtractionSummary &summary )
    {
      for ( const Piece &piece : line.pieces )
      {
        matrix.drawPolyline( piece.pixels, piece.symbol );
        summary.linePx += polylineLength( piece.pixels );
      }
    }
  } // namespace

  LineExtractionSummary extractLines( const cv::Mat &grey, ResultMatrix &matrix, const std::vector<DeadEnd> &continueFrom, bool searchStartingPoints,
                                      const LineExtractionOptions &options, const ExtractionProgress &progress )
  {
    options.check();
    if ( grey.empty() || grey.type() != CV_8UC1 )
      throw std::invalid_argument( "line extraction needs an 8-bit single-band image" );
    if ( matrix.width() != grey.cols || matrix.height() != grey.rows )
      throw std::invalid_argument( "the result matrix must have the image's size" );
    LineExtractionSummary summary;

    // continuation from given dead ends
    for ( const DeadEnd &deadEnd : continueFrom )
    {
      const LineState &s = deadEnd.state;
      if ( nearImageBorder( grey, s.pixelInImage, s.widthPx ) )
        continue;
      const FollowResult line = follow( grey, matrix, s, options, summary );
      ++summary.continued;
      draw( matrix, line, summary );
      summary.deadEnds.push_back( line.end );
    }
    if ( !searchStartingPoints )
      return summary;

    const int size = options.subImageSizePx;
    const int tilesX = ( grey.cols + size - 1 ) / size, tilesY = ( grey.rows + size - 1 ) / size;
    for ( int ty = 0; ty < tilesY; ++ty )
      for ( int tx = 0; tx < tilesX; ++tx )
      {
        if ( progress && !progress( static_cast<double>( ty * tilesX + tx ) / ( tilesX * tilesY ) ) )
        {
          summary.cancelled = true;
          return summary;
        }
        const cv::Rect tile( tx * size, ty * size, std::min( size, grey.cols - tx * size ), std::min( size, grey.rows - ty * size ) );
        Stopwatch t;
        const StartingPointSummary starts = findStartingPoints( grey, tile, options.object, options.start );
        summary.startStage.seconds += t.seconds();
        summary.startStage.imagePixels += static_cast<long>( tile.area() );
        summary.startingPoints += static_cast<int>( starts.points.size() );
        for ( const LineState &start : starts.points )
        {
          if ( matrix.nearestSymbol( start.pixelInImage, std::max( start.widthPx, 6.0 ) ) )
            continue; // on a known line
          LineState backwards = start;
          backwards.direction = -start.direction;
          const FollowResult ahead = follow( grey, matrix, start, options, summary );
          const FollowResult behind = follow( grey, matrix, backwards, options, summary );
          if ( ahead.lemSteps + behind.lemSteps < options.minSteps )
          {
            ++summary.startsRejected;
            continue;
          }
          ++summary.linesStarted;
          matrix.drawPolyline( { start.pixelInImage }, ResultMatrix::kStart, true );
          draw( matrix, ahead, summary );
          draw( matrix, behind, summary );
          summary.deadEnds.push_back( ahead.end );
          summary.deadEnds.push_back( behind.end );
        }
      }
    if ( progress )
      progress( 1.0 );
    return summary;
  }

} // namespace geostation
