/***************************************************************************
  csvtable.h - a CSV table read whole, with messages naming the table
  -------------------------------------------------------------------------
  The trajectory and events tables of a mapping van: a header row, then
  records separated by commas, semicolons or tabs (RFC 4180 quotes within
  a line); blank lines and lines starting with # are skipped. Columns are
  found by name, case-insensitively. A cell that is not a finite number
  where one is needed is refused with the table, the row and the column.
 ***************************************************************************/
#ifndef GEOSTATION_IO_CSVTABLE_H
#define GEOSTATION_IO_CSVTABLE_H

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

namespace geostation
{

  //! One CSV record (RFC 4180 quotes; a quoted field may not span lines here); fields trimmed.
  std::vector<std::string> splitCsvRecord( const std::string &line );

  struct CsvTable
  {
    std::filesystem::path file;
    std::string name; //!< for messages, e.g. "the trajectory table"
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;

    //! The first of `names` (lower case) that the header has.
    std::optional<size_t> column( std::initializer_list<const char *> names ) const;
    //! The cell as a finite number; throws std::invalid_argument naming the table, row (1-based) and column.
    double number( size_t row, size_t column ) const;
    /**
     * The cell as a time in seconds: a number (GPS seconds of the week, seconds
     * of the day, ...) or an ISO 8601 date and time (2026-05-04T10:00:00.417Z;
     * a +hh:mm offset applied; no zone: as written), as seconds since
     * 1970-01-01. Throws std::invalid_argument naming the table, row and column.
     */
    double seconds( size_t row, size_t column ) const;
    //! The cell's text ("" beyond the record's end).
    std::string text( size_t row, size_t column ) const;
    //! "X, Y, Z, ..." for messages.
    std::string headerList() const;
  };

  //! Reads the table; throws std::invalid_argument when it cannot be read or has no rows.
  CsvTable readCsvTable( const std::filesystem::path &file, const std::string &name );

} // namespace geostation

#endif // GEOSTATION_IO_CSVTABLE_H
