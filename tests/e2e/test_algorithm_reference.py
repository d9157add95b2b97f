"""docs/algorithms/ says what the installed algorithms take and give: the
pages regenerated from the provider (scripts/algorithm_reference.py --check)
equal the ones in the repository, and every algorithm has its page.

    test_algorithm_reference.py SOURCE_DIR BUILD_DIR
"""

import os
import shutil
import subprocess
import sys

from headless_support import temporary_profile


def main(source_dir, build_dir):
    tmp, home = temporary_profile(source_dir, build_dir, "geostation-reference-")
    try:
        done = subprocess.run(["/usr/bin/python3", os.path.join(source_dir, "scripts", "algorithm_reference.py"), "--check", "--qgis-home", home,
                               os.path.join(source_dir, "docs", "algorithms")], capture_output=True, text=True)
        sys.stdout.write(done.stdout)
        sys.stderr.write(done.stderr)
        return done.returncode
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
