# Do not run directly: catkin_python_setup() in CMakeLists.txt uses this file.
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(
    packages=['conde_worlds'],
    package_dir={'': 'src'},
))
