/***************************************************************************
  lineextractor.cpp - line extraction in one image
 ***************************************************************************/
#include "extraction/lineextractor.h"
#include "extraction/stopwatch.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "geometry/polyline.h"

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
    if ( subImageOverlapPx < 0 || subImageOverlapPx > subImageSizePx / 2 )
      throw std::invalid_argument( "the sub-images' overlap must be 0 (automatic) to half their size" );
    if ( maxSubImageRuns < 1 )
      throw std::invalid_argument( "the extraction needs at least one run through the sub-images" );
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
      std::optional<LineState> remFrom; //!< where the REM that ended the line in a final break-off started (its piece is the last)
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
        if ( rem.stop == DeadEndKind::FinalBreakOff )
        {
          result.remFrom = state;
          if ( rem.pixels.size() <= 1 )
            result.pieces.push_back( { { state.pixelInImage }, ResultMatrix::kRegional } ); // so that the last piece is REM's
        }
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

    //! Moves a follow's pieces and end from window to image pixels.
    void toImage( FollowResult &line, const GreyWindow &window )
    {
      for ( Piece &piece : line.pieces )
        for ( Eigen::Vector2d &p : piece.pixels )
          p = window.toImage( p );
      line.end.state.pixelInImage = window.toImage( line.end.state.pixelInImage );
      if ( line.remFrom )
        line.remFrom->pixelInImage = window.toImage( line.remFrom->pixelInImage );
    }

    void draw( ResultMatrix &matrix, const FollowResult &line, LineExtractionSummary &summary )
    {
      for ( const Piece &piece : line.pieces )
      {
        matrix.drawPolyline( piece.pixels, piece.symbol );
        summary.linePx += polylineLength( piece.pixels );
      }
    }

    //! The report's mosaic: sub-images of `size` px in raster order, each read with `overlap` px around it.
    class Mosaic
    {
      public:
        Mosaic( const cv::Size &image, int size, int overlap )
          : mImage( image ), mSize( size ), mOverlap( overlap ), mColumns( ( image.width + size - 1 ) / size ), mRows( ( image.height + size - 1 ) / size )
        {}
        int count() const { return mColumns * mRows; }
        cv::Rect core( int index ) const
        {
          const int c = index % mColumns, r = index / mColumns;
          return cv::Rect( c * mSize, r * mSize, mSize, mSize ) & cv::Rect( cv::Point(), mImage );
        }
        cv::Rect window( int index ) const
        {
          const cv::Rect c = core( index );
          return cv::Rect( c.x - mOverlap, c.y - mOverlap, c.width + 2 * mOverlap, c.height + 2 * mOverlap ) & cv::Rect( cv::Point(), mImage );
        }
        int indexOf( const Eigen::Vector2d &pixelInImage ) const
        {
          const int c = std::clamp( static_cast<int>( std::floor( pixelInImage.x() / mSize ) ), 0, mColumns - 1 );
          const int r = std::clamp( static_cast<int>( std::floor( pixelInImage.y() / mSize ) ), 0, mRows - 1 );
          return r * mColumns + c;
        }

      private:
        cv::Size mImage;
        int mSize, mOverlap, mColumns, mRows;
    };

    //! One extraction: the mosaic, the temporary dead ends waiting in each sub-image, the summary.
    class MosaicExtraction
    {
      public:
        MosaicExtraction( const GreyTiles &grey, ResultMatrix &matrix, const LineExtractionOptions &options )
          : mGrey( grey ), mMatrix( matrix ), mOptions( options ), mMosaic( grey.size(), options.subImageSizePx, options.overlapPx() ), mWaiting( mMosaic.count() )
        {}

        void wait( const DeadEnd &deadEnd ) { mWaiting[mMosaic.indexOf( deadEnd.state.pixelInImage )].push_back( deadEnd ); }
        bool waiting( int index ) const { return !mWaiting[index].empty(); }
        bool anyWaiting() const
        {
          return std::any_of( mWaiting.begin(), mWaiting.end(), []( const std::vector<DeadEnd> &w ) { return !w.empty(); } );
        }
        int count() const { return mMosaic.count(); }
        LineExtractionSummary &summary() { return mSummary; }

        //! Continues the lines waiting in sub-image `index`, then (with `search`) follows its starting points.
        void process( int index, bool search )
        {
          const GreyWindow window = mGrey.window( mMosaic.window( index ) );
          // lines already known a little beyond the window (the matrix is held whole): a line ending at the window's
          // edge next to one is joined to it here, not continued past it in the next sub-image
          const cv::Rect wider( window.origin.x - mOptions.overlapPx(), window.origin.y - mOptions.overlapPx(), window.pixels.cols + 2 * mOptions.overlapPx(),
                                window.pixels.rows + 2 * mOptions.overlapPx() );
          const ResultMatrix known = mMatrix.view( wider, window.origin );
          ++mSummary.subImages;
          std::vector<DeadEnd> waiting;
          waiting.swap( mWaiting[index] );
          for ( const DeadEnd &deadEnd : waiting )
          {
            LineState s = deadEnd.state;
            s.pixelInImage = window.toWindow( s.pixelInImage );
            FollowResult line = follow( window.pixels, known, s, mOptions, mSummary );
            toImage( line, window );
            ++mSummary.continued;
            // a line continued here that got no further does not wait again
            const bool moved = line.lemSteps > 0 || ( line.end.state.pixelInImage - deadEnd.state.pixelInImage ).norm() >= 1.0;
            const std::optional<int> next = settle( line, index, window.rect(), deadEnd.kind != DeadEndKind::SubImageBorder || moved );
            finish( line, next );
          }
          if ( !search )
            return;
          const cv::Rect core = mMosaic.core( index );
          Stopwatch t;
          const StartingPointSummary starts = findStartingPoints( window.pixels, core - window.origin, mOptions.object, mOptions.start );
          mSummary.startStage.seconds += t.seconds();
          mSummary.startStage.imagePixels += static_cast<long>( core.area() );
          mSummary.startingPoints += static_cast<int>( starts.points.size() );
          for ( const LineState &start : starts.points )
          {
            if ( known.nearestSymbol( start.pixelInImage, std::max( start.widthPx, 6.0 ) ) || besideKnownBand( window.toImage( start.pixelInImage ), start.widthPx ) )
              continue; // on a known line, or on a marking, kerb or shoulder along one
            LineState backwards = start;
            backwards.direction = -start.direction;
            FollowResult ahead = follow( window.pixels, known, start, mOptions, mSummary );
            FollowResult behind = follow( window.pixels, known, backwards, mOptions, mSummary );
            if ( ahead.lemSteps + behind.lemSteps < mOptions.minSteps )
            {
              ++mSummary.startsRejected;
              continue;
            }
            toImage( ahead, window );
            toImage( behind, window );
            ++mSummary.linesStarted;
            mMatrix.drawPolyline( { window.toImage( start.pixelInImage ) }, ResultMatrix::kStart, true );
            const std::optional<int> nextAhead = settle( ahead, index, window.rect(), true ), nextBehind = settle( behind, index, window.rect(), true );
            recordBand( ahead, behind, start.widthPx );
            finish( ahead, nextAhead );
            finish( behind, nextBehind );
          }
        }

        //! What is left waiting after the last run stays where it is, as a dead end.
        void giveUp()
        {
          for ( std::vector<DeadEnd> &waiting : mWaiting )
          {
            mSummary.deadEnds.insert( mSummary.deadEnds.end(), waiting.begin(), waiting.end() );
            waiting.clear();
          }
        }

      private:
        /**
         * A road is one band, whatever lines run along it: a starting point
         * whose band lies within a line started before (its band and this
         * one side by side, 2 px apart at most) is a marking, kerb or
         * shoulder of that road, not a road of its own. (Starting points come
         * strongest and widest first, so the road is found before its lines.)
         */
        bool besideKnownBand( const Eigen::Vector2d &pixelInImage, double widthPx ) const
        {
          for ( const KnownBand &band : mBands )
          {
            const double reach = 0.5 * ( band.widthPx + widthPx ) + 2.0;
            if ( pixelInImage.x() < band.low.x() - reach || pixelInImage.y() < band.low.y() - reach || pixelInImage.x() > band.high.x() + reach ||
                 pixelInImage.y() > band.high.y() + reach )
              continue;
            for ( const std::vector<Eigen::Vector2d> &piece : band.pieces )
              for ( size_t i = 0; i + 1 < piece.size(); ++i )
                if ( distanceToSegment( pixelInImage, piece[i], piece[i + 1] ) <= reach )
                  return true;
          }
          return false;
        }

        void recordBand( const FollowResult &ahead, const FollowResult &behind, double widthPx )
        {
          KnownBand band;
          band.widthPx = widthPx;
          band.low = Eigen::Vector2d::Constant( std::numeric_limits<double>::max() );
          band.high = -band.low;
          for ( const FollowResult *line : { &ahead, &behind } )
            for ( const Piece &piece : line->pieces )
            {
              band.pieces.push_back( piece.pixels );
              for ( const Eigen::Vector2d &p : piece.pixels )
              {
                band.low = band.low.cwiseMin( p );
                band.high = band.high.cwiseMax( p );
              }
            }
          mBands.push_back( std::move( band ) );
        }

        /**
         * Where a line that stopped goes on. At its window's edge inside the image: in the sub-image it points
         * into. A final break-off of REM whose area of interest reached to the window's edge (the profiles
         * there cut, where the whole image would have shown the line), or that lies in the overlap, may be the
         * window's doing: REM's piece is taken back and the line goes on from where REM started, in the
         * sub-image that holds that point or the one REM's area reaches into - whose window sees all around
         * it - once; a line that gets no further there ends. Nothing: the stop is final.
         */
        std::optional<int> settle( FollowResult &line, int index, const cv::Rect &window, bool mayWait ) const
        {
          const LineState &s = line.end.state;
          const cv::Size image = mGrey.size();
          if ( line.end.kind == DeadEndKind::ImageBorder && !nearImageBorder( image, s.pixelInImage + lemStepPx( mOptions.lem, s.widthPx ) * s.direction, s.widthPx ) )
          {
            int next = mMosaic.indexOf( s.pixelInImage );
            if ( next == index ) // stopped inside this sub-image's core (a long jump of REM): the one it points into
              next = mMosaic.indexOf( s.pixelInImage + mOptions.overlapPx() * s.direction );
            if ( next == index )
            {
              line.end.kind = DeadEndKind::FinalBreakOff;
              return std::nullopt;
            }
            return next;
          }
          if ( line.end.kind != DeadEndKind::FinalBreakOff || !line.remFrom || !mayWait )
            return std::nullopt;
          const LineState &from = *line.remFrom;
          const Eigen::Vector2d reach = from.pixelInImage + ( mOptions.rem.areaAhead( from ).lengthPx + from.widthPx ) * from.direction;
          std::optional<int> next;
          if ( mMosaic.indexOf( from.pixelInImage ) != index )
            next = mMosaic.indexOf( from.pixelInImage );
          else if ( nearImageBorder( window.size(), reach - Eigen::Vector2d( window.x, window.y ), from.widthPx ) && !nearImageBorder( image, reach, from.widthPx ) )
            next = mMosaic.indexOf( reach );
          if ( !next || *next == index )
            return std::nullopt;
          line.pieces.pop_back();
          line.end.state = from;
          return next;
        }

        //! Draws a line and records or queues its end.
        void finish( FollowResult &line, const std::optional<int> &next )
        {
          draw( mMatrix, line, mSummary );
          if ( !next )
          {
            mSummary.deadEnds.push_back( line.end );
            return;
          }
          line.end.kind = DeadEndKind::SubImageBorder;
          ++mSummary.temporaryDeadEnds;
          mWaiting[*next].push_back( line.end );
        }

        const GreyTiles &mGrey;
        ResultMatrix &mMatrix;
        const LineExtractionOptions &mOptions;
        Mosaic mMosaic;
        std::vector<std::vector<DeadEnd>> mWaiting; //!< temporary and given dead ends, by sub-image (image pixels)
        struct KnownBand
        {
          std::vector<std::vector<Eigen::Vector2d>> pieces; //!< of a started line, both ways, in image pixels
          double widthPx = 0.0;
          Eigen::Vector2d low, high; //!< bounds of the pieces
        };
        std::vector<KnownBand> mBands; //!< the lines started in this extraction
        LineExtractionSummary mSummary;
    };
  } // namespace

  int LineExtractionOptions::overlapPx() const
  {
    return subImageOverlapPx > 0 ? subImageOverlapPx : std::max( 32, static_cast<int>( std::ceil( 3.0 * object.maxWidthPx ) ) + 16 );
  }

  LineExtractionSummary extractLines( const GreyTiles &grey, ResultMatrix &matrix, const std::vector<DeadEnd> &continueFrom, bool searchStartingPoints,
                                      const LineExtractionOptions &options, const Progress &progress )
  {
    options.check();
    if ( matrix.width() != grey.width() || matrix.height() != grey.height() )
      throw std::invalid_argument( "the result matrix must have the image's size" );
    MosaicExtraction extraction( grey, matrix, options );
    for ( const DeadEnd &deadEnd : continueFrom )
      if ( !nearImageBorder( grey.size(), deadEnd.state.pixelInImage, deadEnd.state.widthPx ) )
        extraction.wait( deadEnd );
    LineExtractionSummary &summary = extraction.summary();
    for ( int run = 0; run < options.maxSubImageRuns; ++run )
    {
      const bool search = searchStartingPoints && run == 0;
      if ( !search && !extraction.anyWaiting() )
        break;
      ++summary.subImageRuns;
      for ( int index = 0; index < extraction.count(); ++index )
      {
        if ( !search && !extraction.waiting( index ) )
          continue;
        // the first run is most of the work; later runs only finish lines
        if ( !progress.report( 0.95 * ( run == 0 ? static_cast<double>( index ) / extraction.count() : 1.0 ),
                               "sub-image " + std::to_string( index + 1 ) + " of " + std::to_string( extraction.count() ) ) )
        {
          summary.cancelled = true;
          return summary;
        }
        extraction.process( index, search );
      }
    }
    extraction.giveUp();
    progress.report( 1.0 );
    return summary;
  }

  LineExtractionSummary extractLines( const cv::Mat &grey, ResultMatrix &matrix, const std::vector<DeadEnd> &continueFrom, bool searchStartingPoints,
                                      const LineExtractionOptions &options, const Progress &progress )
  {
    return extractLines( GreyTiles( grey ), matrix, continueFrom, searchStartingPoints, options, progress );
  }

} // namespace geostation


