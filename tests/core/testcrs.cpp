// docs/conventions.md §4: the block CRS must be projected (or engineering) in metres.
#include <gtest/gtest.h>

#include "geometry/crs.h"

using namespace geostation;

TEST( Crs, ProjectedMetresAccepted )
{
  EXPECT_NO_THROW( requireProjectedMetricCrs( "EPSG:32617" ) );
  EXPECT_NO_THROW( requireProjectedMetricCrs( "EPSG:2056" ) );
  EXPECT_NO_THROW( requireProjectedMetricCrs( "EPSG:32617+5703" ) ); // compound: UTM + NAVD88 height
  EXPECT_NO_THROW( requireProjectedMetricCrs( "+proj=utm +zone=33 +datum=WGS84 +units=m +type=crs" ) );
  EXPECT_EQ( describeCrs( "EPSG:32617" ).name, "WGS 84 / UTM zone 17N" );
  EXPECT_EQ( describeCrs( "EPSG:32617" ).unitName, "metre" );
}

TEST( Crs, LocalEngineeringCrsAccepted )
{
  const std::string wkt = R"wkt(ENGCRS["Site grid",EDATUM["Site datum"],CS[Cartesian,2],AXIS["easting (x)",east,ORDER[1],LENGTHUNIT["metre",1]],AXIS["northing (y)",north,ORDER[2],LENGTHUNIT["metre",1]]])wkt";
  EXPECT_NO_THROW( requireProjectedMetricCrs( wkt ) );
  EXPECT_EQ( describeCrs( wkt ).kind, "engineering" );
}

TEST( Crs, GeographicRefusedWithAClearMessage )
{
  try
  {
    requireProjectedMetricCrs( "EPSG:4326" );
    FAIL() << "a geographic CRS was accepted";
  }
  catch ( const std::invalid_argument &e )
  {
    const std::string msg = e.what();
    EXPECT_NE( msg.find( "geographic" ), std::string::npos ) << msg;
    EXPECT_NE( msg.find( "projected CRS in metres" ), std::string::npos ) << msg;
  }
}

TEST( Crs, FeetRefused )
{
  try
  {
    requireProjectedMetricCrs( "EPSG:2263" ); // NY Long Island, US survey feet
    FAIL() << "a CRS in feet was accepted";
  }
  catch ( const std::invalid_argument &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "foot" ), std::string::npos ) << e.what();
  }
}

TEST( Crs, GeocentricAndGarbageRefused )
{
  EXPECT_THROW( requireProjectedMetricCrs( "EPSG:4978" ), std::invalid_argument );
  EXPECT_THROW( requireProjectedMetricCrs( "not a crs" ), std::invalid_argument );
  EXPECT_THROW( requireProjectedMetricCrs( "" ), std::invalid_argument );
}
