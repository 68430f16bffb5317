"""Build the optional native CGAL Delaunay module (everything else is in pyproject.toml).

``crustview.core._delaunay3`` wraps CGAL's ``Delaunay_triangulation_3``
(header-only, from Debian's ``libcgal-dev``; ``scripts/install.sh`` installs
it).  The extension is optional: without CGAL's headers or a C++ compiler the
build skips it and crustview falls back to the ``cgal`` wheel, then Qhull.
"""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "crustview.core._delaunay3",
            sources=["crustview/core/_delaunay3.cpp"],
            language="c++",
            extra_compile_args=["-std=c++17", "-O2", "-DNDEBUG", "-DCGAL_NDEBUG"],
            libraries=["gmp", "mpfr"],
            optional=True,
        )
    ]
)
