/***************************************************************************
  testfiles.h - helpers of the file-format tests: a fresh temporary folder,
  the message of an exception
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_TESTFILES_H
#define GEOSTATION_TESTS_TESTFILES_H

#include <filesystem>
#include <functional>
#include <string>

#include <unistd.h>

namespace geostation::testing
{

  //! An empty folder under the system's temporary folder, unique to the test process.
  inline std::filesystem::path freshTestFolder( const std::string &name )
  {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-" + name + "-" + std::to_string( ::getpid() ) );
    std::filesystem::remove_all( dir );
    std::filesystem::create_directories( dir );
    return dir;
  }

  //! What `f` throws, or "(no error)".
  inline std::string errorOf( const std::function<void()> &f )
  {
    try
    {
      f();
    }
    catch ( const std::exception &e )
    {
      return e.what();
    }
    return "(no error)";
  }

} // namespace geostation::testing

#endif // GEOSTATION_TESTS_TESTFILES_H
