import os
import sys

sys.path.insert(0, os.path.dirname(__file__))


def pytest_addoption(parser):
    parser.addoption(
        "--update-gallery",
        action="store_true",
        default=False,
        help="draw the gallery's pictures (docs/img/gallery/) again from its pages' code",
    )
    parser.addoption(
        "--update-golden",
        action="store_true",
        default=False,
        help="rewrite the golden files in tests/golden/ from the current output (then review "
        "the diff before committing)",
    )
