/***************************************************************************
  testcontrolmarks.cpp - control identified on marks of every size
  -------------------------------------------------------------------------
  A photo from a 12 m mast over 16 signalised targets (a white disc in a
  dark ring) and 10 decoys, rendered by the independent generator of
  mastscene.h: the targets are some 60 px across near the mast and 8 px
  far off, ellipses flattened by the view. With default options 90 % of
  the targets wholly in the frame should be found, none claimed more than
  1 px from its true centre (the projected centre of the disc, not the
  centre of its ellipse), and those of 12 px or more within 0.3 px.
 ***************************************************************************/
#include <cstdio>

#include <gtest/gtest.h>

#include "identification/photoidentification.h"
#include "mastscene.h"

using namespace geostation;
using namespace geostation::mastscene;

TEST( ControlMarks, TargetsFromNearToFarOnAMastPhoto )
{
  for ( const uint32_t seed : { 1u, 2u, 3u } )
  {
    SCOPED_TRACE( seed );
    const MastScene scene = mastScene( seed );
    const PhotoIdentificationSummary s = identifyControlInPhoto( scene.grey, scene.camera, std::nullopt, scene.control );
    std::printf( "seed %u: %s (%d candidates)\n", seed, s.identification.message.c_str(), s.candidates );
    std::map<std::string, const PhotoIdentifiedPoint *> claimed;
    for ( const PhotoIdentifiedPoint &p : s.identified )
      claimed[p.pointId] = &p;
    int found = 0, farOff = 0, whole = 0, foundWhole = 0;
    double worst = 0.0, worstLarge = 0.0;
    for ( const ControlPoint &c : scene.control )
    {
      const auto it = claimed.find( c.id );
      const double error = it == claimed.end() ? -1.0 : ( it->second->pixelInFile - scene.truePixel.at( c.id ) ).norm();
      const bool inFrame = scene.wholeInFrame.at( c.id );
      whole += inFrame ? 1 : 0;
      std::printf( "  %s  %5.1f px across%s  %s", c.id.c_str(), scene.acrossPx.at( c.id ), inFrame ? "" : " (cut by the frame)", it == claimed.end() ? "not found\n" : "" );
      if ( it == claimed.end() )
        continue;
      std::printf( "%.2f px off%s\n", error, it->second->relocated ? " (relocated)" : "" );
      ++found;
      foundWhole += inFrame ? 1 : 0;
      farOff += error > 1.0 ? 1 : 0;
      worst = std::max( worst, error );
      worstLarge = std::max( worstLarge, scene.acrossPx.at( c.id ) >= 12.0 ? error : 0.0 );
    }
    std::printf( "  found %d of %zu (%d of the %d wholly in the frame), worst %.2f px (%.2f px on marks of 12 px or more), %d more than 1 px off\n", found,
                 scene.control.size(), foundWhole, whole, worst, worstLarge, farOff );
    EXPECT_GE( foundWhole, 0.9 * whole );
    EXPECT_EQ( farOff, 0 );
    EXPECT_LE( worstLarge, 0.3 ); // the centre of a disc seen obliquely, not of its ellipse
  }
}
