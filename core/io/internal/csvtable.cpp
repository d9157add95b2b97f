/***************************************************************************
  csvtable.cpp - a CSV table read whole, with messages naming the table
 ***************************************************************************/
#include "io/internal/csvtable.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <fstream>
#include <stdexcept>

#include "io/textfile.h"

namespace geostation
{
  namespace
  {
    std::string trim( const std::string &s )
    {
      const size_t a = s.find_first_not_of( " \t\r\n" );
      if ( a == std::string::npos )
        return {};
      return s.substr( a, s.find_last_not_of( " \t\r\n" ) - a + 1 );
    }
  } // namespace

  std::vector<std::string> splitCsvRecord( const std::string &line )
  {
    std::vector<std::string> fields( 1 );
    bool quoted = false;
    for ( size_t i = 0; i < line.size(); ++i )
    {
      const char c = line[i];
      if ( quoted )
      {
        if ( c == '"' && i + 1 < line.size() && line[i + 1] == '"' )
          fields.back() += '"', ++i;
        else if ( c == '"' )
          quoted = false;
        else
          fields.back() += c;
      }
      else if ( c == '"' )
        quoted = true;
      else if ( c == ',' || c == ';' || c == '\t' )
        fields.emplace_back();
      else
        fields.back() += c;
    }
    for ( std::string &f : fields )
      f = trim( f );
    return fields;
  }

  std::optional<size_t> CsvTable::column( std::initializer_list<const char *> names ) const
  {
    for ( const char *name : names )
      for ( size_t i = 0; i < header.size(); ++i )
        if ( asciiLower( header[i] ) == name )
          return i;
    return std::nullopt;
  }

  double CsvTable::number( size_t row, size_t column ) const
  {
    const std::string &cell = column < rows[row].size() ? rows[row][column] : std::string();
    char *end = nullptr;
    const double v = std::strtod( cell.c_str(), &end );
    if ( cell.empty() || *end != '\0' || !std::isfinite( v ) )
      throw std::invalid_argument( name + " " + file.string() + ", row " + std::to_string( row + 1 ) + ": \"" + header[column] + "\" is \"" + cell + "\", not a number" );
    return v;
  }

  namespace
  {
    //! Days from 1970-01-01 to a date of the proleptic Gregorian calendar.
    long daysFromCivil( long y, long m, long d )
    {
      y -= m <= 2;
      const long era = ( y >= 0 ? y : y - 399 ) / 400;
      const long yoe = y - era * 400;
      const long doy = ( 153 * ( m + ( m > 2 ? -3 : 9 ) ) + 2 ) / 5 + d - 1;
      const long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
      return era * 146097 + doe - 719468;
    }

    //! YYYY-MM-DD[T ]hh:mm:ss[.fff][Z|+hh:mm|-hh:mm] as seconds since 1970-01-01, or NaN.
    double isoSeconds( const std::string &text )
    {
      int y, mo, d, h, mi, consumed = 0;
      if ( std::sscanf( text.c_str(), "%4d-%2d-%2d%*1[T ]%2d:%2d%n", &y, &mo, &d, &h, &mi, &consumed ) != 5 || consumed == 0 )
        return std::numeric_limits<double>::quiet_NaN();
      std::string rest = text.substr( static_cast<size_t>( consumed ) );
      double sec = 0.0;
      if ( !rest.empty() && rest[0] == ':' )
      {
        char *end = nullptr;
        sec = std::strtod( rest.c_str() + 1, &end );
        rest = end;
      }
      double offsetS = 0.0;
      if ( rest == "Z" || rest.empty() )
        offsetS = 0.0;
      else
      {
        int oh = 0, om = 0;
        char sign = 0;
        if ( std::sscanf( rest.c_str(), "%c%2d:%2d", &sign, &oh, &om ) != 3 || ( sign != '+' && sign != '-' ) )
          return std::numeric_limits<double>::quiet_NaN();
        offsetS = ( sign == '+' ? 1 : -1 ) * ( oh * 3600.0 + om * 60.0 );
      }
      if ( mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || !( sec >= 0.0 && sec < 61.0 ) )
        return std::numeric_limits<double>::quiet_NaN();
      return daysFromCivil( y, mo, d ) * 86400.0 + h * 3600.0 + mi * 60.0 + sec - offsetS;
    }
  } // namespace

  double CsvTable::seconds( size_t row, size_t column ) const
  {
    const std::string cell = text( row, column );
    char *end = nullptr;
    const double v = std::strtod( cell.c_str(), &end );
    if ( !cell.empty() && *end == '\0' && std::isfinite( v ) )
      return v;
    const double iso = isoSeconds( cell );
    if ( std::isfinite( iso ) )
      return iso;
    throw std::invalid_argument( name + " " + file.string() + ", row " + std::to_string( row + 1 ) + ": \"" + header[column] + "\" is \"" + cell
                                 + "\", neither seconds nor an ISO 8601 time (2026-05-04T10:00:00.417Z)" );
  }

  std::string CsvTable::text( size_t row, size_t column ) const { return column < rows[row].size() ? rows[row][column] : std::string(); }

  std::string CsvTable::headerList() const
  {
    std::string s;
    for ( const std::string &h : header )
      s += ( s.empty() ? "" : ", " ) + h;
    return s;
  }

  CsvTable readCsvTable( const std::filesystem::path &file, const std::string &name )
  {
    std::ifstream in( file );
    if ( !in )
      throw std::invalid_argument( name + " " + file.string() + " does not exist or cannot be read" );
    CsvTable t;
    t.file = file;
    t.name = name;
    std::string line;
    while ( std::getline( in, line ) )
    {
      if ( trim( line ).empty() || trim( line )[0] == '#' )
        continue;
      if ( t.header.empty() )
        t.header = splitCsvRecord( line );
      else
        t.rows.push_back( splitCsvRecord( line ) );
    }
    if ( t.header.empty() || t.rows.empty() )
      throw std::invalid_argument( name + " " + file.string() + " has no rows" );
    return t;
  }

} // namespace geostation
