/***************************************************************************
  testterrainheight.cpp - the mean terrain height of a pair, by matching
  -------------------------------------------------------------------------
  On pairs painted by paintedpair.h, not by the simulator: fields in rows
  of their own direction and spacing at 2000 and 4000 px across, and a
  texture that repeats the same way everywhere. Searched along the whole
  epipolar curve, the 4000 px pair of the repeating texture had its grid
  points take the aliases as often as the terrain, and the median claimed
  -151 m over terrain at 120 m (spread 213 m). The height band most points
  share holds where aliases differ from point to point; where they are
  shared as widely, no height is claimed.
 ***************************************************************************/
#include <gtest/gtest.h>

#include "extraction/terrainheight.h"
#include "matching/matchimage.h"
#include "paintedpair.h"

using namespace geostation;
using namespace geostation::paintedpair;

namespace
{
  TerrainHeightEstimate estimate( const PaintedPair &pair )
  {
    const OrientedImage a( pair.camera, pair.exterior[0] ), b( pair.camera, pair.exterior[1] );
    const MatchImage imageA( pair.grey[0] ), imageB( pair.grey[1] );
    return estimateTerrainHeight( a, b, imageA, imageB );
  }
}

TEST( TerrainHeight, FieldsInRowsAtTwoImageSizes )
{
  for ( const int width : { 2000, 4000 } )
  {
    SCOPED_TRACE( width );
    const PaintedPair pair = paintedPair( width, Texture::Rows );
    const TerrainHeightEstimate e = estimate( pair );
    ASSERT_TRUE( e.ok() ) << e.message;
    std::printf( "rows, %d px: %.2f m (truth %.2f), %d points matched, %d voting, spread %.2f m\n", width, e.heightM, pair.terrainM, e.points, e.votingPoints,
                 e.spreadM );
    EXPECT_NEAR( e.heightM, pair.terrainM, 0.5 );
    EXPECT_GE( e.points, 20 );
    EXPECT_LE( e.spreadM, 1.0 );
  }
}

TEST( TerrainHeight, ATextureThatRepeatsEverywhereIsSaidTo )
{
  // at 2000 px the curve is short enough for the right place to win; at 4000 px its aliases are shared as widely
  const PaintedPair small = paintedPair( 2000, Texture::Repeating );
  const TerrainHeightEstimate e = estimate( small );
  ASSERT_TRUE( e.ok() ) << e.message;
  EXPECT_NEAR( e.heightM, small.terrainM, 0.5 );
  const TerrainHeightEstimate large = estimate( paintedPair( 4000, Texture::Repeating ) );
  if ( large.ok() )
    EXPECT_NEAR( large.heightM, small.terrainM, 0.5 ) << "a height claimed must be the terrain's";
  else
  {
    EXPECT_EQ( large.status, TerrainHeightEstimate::Status::RepeatingTexture ) << large.message;
    EXPECT_NE( large.message.find( "the texture repeats" ), std::string::npos ) << large.message;
  }
  std::printf( "repeating, 4000 px: %s\n", large.ok() ? std::to_string( large.heightM ).c_str() : large.message.c_str() );
}
