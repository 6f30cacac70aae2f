"""python3 -m calibench_report --out REPORT_DIR DIR...: see cli.py."""
import sys

from calibench_report.cli import main

sys.exit(main())
