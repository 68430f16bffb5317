"""Build the optional native CGAL Delaunay modules (everything else is in pyproject.toml).

``crustview.core.delaunay._delaunay3`` wraps CGAL's ``Delaunay_triangulation_3`` and
``crustview.core.delaunay._delaunay_d`` its dD ``Delaunay_triangulation`` in R^4 and
R^5 (header-only, from Debian's ``libcgal-dev``; the dD kernel also needs
Eigen's headers, ``libeigen3-dev``; ``scripts/install.sh`` installs both).
Both are optional: without the headers or a C++ compiler the build skips them
and crustview falls back to the ``cgal`` wheel (R^3) and Qhull.
``crustview.core.delaunay._faces`` (no third-party code) lists the faces of a
triangulation and the simplices around each, ``crustview.core.delaunay._poles`` runs
Algorithm 1's greedy rounds, ``crustview.core.delaunay._segments`` and
``crustview.core.delaunay._cellpass`` the first steps of Algorithm 2's cocone score in
codimension 1 and 2, ``crustview.core.delaunay._literal`` its literal test on triangles,
``crustview.core.delaunay._centres`` the simplices' circumcentres and
``crustview.core.paper._prune`` Algorithm 3's loop, ``crustview.core.analysis._components``
graph components, ``crustview.core.util._surface`` a triangle complex's edge table and topology counts,
``crustview.core.analysis._spacing`` the local spacing's enclosing radii
and ``crustview.core.analysis._paths`` the loop basis's shortest-path trees; without them
numpy, scipy and Python do the same.
"""

from setuptools import Extension, setup

FLAGS = ["-std=c++17", "-O3", "-DNDEBUG", "-DCGAL_NDEBUG"]
#: crustview's own kernels that give numpy's values bit for bit: no fused multiply-add (-ffp-contract=off),
#: so the build machine's vector units can be used (-march=native: the install builds where it runs) without
#: changing a value.  Measured (README, issue 21's eleventh round): Algorithm 1's poles 0.63-0.67 -> 0.36-0.46 s on the
#: flat Klein bottle at 10k points, results identical.  The CGAL modules keep the generic target: CGAL's
#: filtered predicates rely on its interval arithmetic's rounding, which contraction may break.
EXACT = [*FLAGS, "-ffp-contract=off", "-march=native"]

setup(
    ext_modules=[
        Extension(
            "crustview.core.delaunay._delaunay3",
            sources=["crustview/core/delaunay/_delaunay3.cpp"],
            depends=["crustview/core/delaunay/_cgal_buffers.h"],
            language="c++",
            extra_compile_args=[*FLAGS, "-pthread"],  # the cells and their neighbours written on two threads
            extra_link_args=["-pthread"],
            libraries=["gmp", "mpfr"],
            optional=True,
        ),
        Extension(  # no third-party headers: the face lists of Algorithm 2 (see core/delaunay/faces.py)
            "crustview.core.delaunay._faces",
            sources=["crustview/core/delaunay/_faces.cpp"],
            language="c++",
            extra_compile_args=FLAGS,
            optional=True,
        ),
        Extension(  # no third-party headers: Algorithm 1's greedy rounds (see core/paper/normals.py)
            "crustview.core.delaunay._poles",
            sources=["crustview/core/delaunay/_poles.cpp"],
            language="c++",
            # no fused multiply-add: the same sums, bit for bit, as the numpy code
            extra_compile_args=EXACT,
            optional=True,
        ),
        Extension(  # no third-party headers: Algorithm 2's codimension-1 segment ends (core/paper/candidates.py)
            "crustview.core.delaunay._segments",
            sources=["crustview/core/delaunay/_segments.cpp"],
            language="c++",
            extra_compile_args=EXACT,
            optional=True,
        ),
        Extension(  # no third-party headers: Algorithm 2's codimension-2 vertex pass (core/paper/candidates.py)
            "crustview.core.delaunay._cellpass",
            sources=["crustview/core/delaunay/_cellpass.cpp"],
            language="c++",
            extra_compile_args=EXACT,
            optional=True,
        ),
        Extension(  # no third-party headers: Algorithm 2's literal test on triangles (core/paper/literal.py)
            "crustview.core.delaunay._literal",
            sources=["crustview/core/delaunay/_literal.cpp"],
            language="c++",
            extra_compile_args=EXACT,
            optional=True,
        ),
        Extension(  # no third-party headers: the Delaunay simplices' circumcentres (core/delaunay/triangulation.py)
            "crustview.core.delaunay._centres",
            sources=["crustview/core/delaunay/_centres.cpp"],
            language="c++",
            extra_compile_args=EXACT,
            optional=True,
        ),
        Extension(  # no third-party headers: Algorithm 3's loop (core/paper/extraction.py)
            "crustview.core.paper._prune",
            sources=["crustview/core/paper/_prune.cpp"],
            language="c++",
            # no fused multiply-add: the same dot products, bit for bit, as the Python loop
            extra_compile_args=EXACT,
            optional=True,
        ),
        Extension(  # no third-party headers: graph components with scipy's labels (core/analysis/topology.py)
            "crustview.core.analysis._components",
            sources=["crustview/core/analysis/_components.cpp"],
            depends=["crustview/core/util/_union_find.h"],
            language="c++",
            extra_compile_args=FLAGS,
            optional=True,
        ),
        Extension(  # no third-party headers: a boundary matrix's rank over GF(2) (core/analysis/ranks.py)
            "crustview.core.analysis._gf2",
            sources=["crustview/core/analysis/_gf2.cpp"],
            language="c++",
            extra_compile_args=FLAGS,
            optional=True,
        ),
        Extension(  # no third-party headers: a triangle complex's edge table and topology counts (core/util)
            "crustview.core.util._surface",
            sources=["crustview/core/util/_surface.cpp"],
            depends=["crustview/core/util/_union_find.h"],
            language="c++",
            extra_compile_args=FLAGS,
            optional=True,
        ),
        Extension(  # no third-party headers: the local spacing's enclosing radii (core/analysis/features.py)
            "crustview.core.analysis._spacing",
            sources=["crustview/core/analysis/_spacing.cpp"],
            language="c++",
            extra_compile_args=FLAGS,
            extra_link_args=["-pthread"],
            optional=True,
        ),
        Extension(  # no third-party headers: shortest-path trees on two threads (core/analysis/loops.py)
            "crustview.core.analysis._paths",
            sources=["crustview/core/analysis/_paths.cpp"],
            language="c++",
            extra_compile_args=FLAGS,
            extra_link_args=["-pthread"],
            optional=True,
        ),
        Extension(  # no third-party headers: the robust extension's cell labelling (core/robust/labelling.py)
            "crustview.core.robust._labels",
            sources=["crustview/core/robust/_labels.cpp"],
            language="c++",
            extra_compile_args=FLAGS,
            extra_link_args=["-pthread"],
            optional=True,
        ),
        Extension(
            "crustview.core.delaunay._delaunay_d",
            sources=["crustview/core/delaunay/_delaunay_d.cpp"],
            depends=["crustview/core/delaunay/_cgal_buffers.h"],
            include_dirs=["/usr/include/eigen3"],
            language="c++",
            extra_compile_args=[*FLAGS, "-pthread"],  # the cells and their neighbours written on two threads
            extra_link_args=["-pthread"],
            libraries=["gmp", "mpfr"],
            optional=True,
        ),
    ]
)
