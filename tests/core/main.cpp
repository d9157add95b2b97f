// The core tests' main: GoogleTest's, and a filter that selects nothing is
// a failure. CTest runs the tests that share a simulated scene as one test
// with a --gtest_filter naming them (tests/core/CMakeLists.txt); GoogleTest
// itself passes a filter that matches no test, so a test renamed or moved
// out of its group would leave the group empty and the suite green. Each
// ':'-separated pattern of the filter's positive part must select at least
// one test that runs.
#include <fnmatch.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  std::vector<std::string> positivePatterns( const std::string &filter )
  {
    const std::string positive = filter.substr( 0, filter.find( '-' ) );
    std::vector<std::string> patterns;
    std::stringstream in( positive );
    for ( std::string p; std::getline( in, p, ':' ); )
      if ( !p.empty() )
        patterns.push_back( p );
    return patterns;
  }

  //! The patterns of the filter that select no test that runs (a disabled test does not run unless asked for).
  std::vector<std::string> patternsSelectingNothing( const std::string &filter )
  {
    const testing::UnitTest &unit = *testing::UnitTest::GetInstance();
    const bool disabledToo = GTEST_FLAG_GET( also_run_disabled_tests );
    std::vector<std::string> empty;
    for ( const std::string &pattern : positivePatterns( filter ) )
    {
      bool selects = false;
      for ( int s = 0; s < unit.total_test_suite_count() && !selects; ++s )
      {
        const testing::TestSuite &suite = *unit.GetTestSuite( s );
        for ( int t = 0; t < suite.total_test_count() && !selects; ++t )
        {
          const std::string name = std::string( suite.name() ) + "." + suite.GetTestInfo( t )->name();
          const bool disabled = name.find( "DISABLED_" ) != std::string::npos;
          selects = fnmatch( pattern.c_str(), name.c_str(), 0 ) == 0 && ( disabledToo || !disabled );
        }
      }
      if ( !selects )
        empty.push_back( pattern );
    }
    return empty;
  }
} // namespace

int main( int argc, char **argv )
{
  testing::InitGoogleTest( &argc, argv );
  if ( !GTEST_FLAG_GET( list_tests ) )
  {
    const std::vector<std::string> empty = patternsSelectingNothing( GTEST_FLAG_GET( filter ) );
    for ( const std::string &pattern : empty )
      std::fprintf( stderr,
                    "The filter's pattern \"%s\" selects no test that runs: a test renamed, moved out of its group (tests/core/CMakeLists.txt) "
                    "or disabled (--gtest_also_run_disabled_tests runs those).\n",
                    pattern.c_str() );
    if ( !empty.empty() )
      return 1;
  }
  return RUN_ALL_TESTS();
}
