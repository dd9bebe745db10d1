# Sourced by the project's scripts: the environment every ROS tool here needs.
# Debian's ROS 1 lives in /usr; a pyenv (or any other) python3 first on PATH lacks the ROS
# Python modules, so /usr/bin goes first and catkin is told which interpreter to use.
export PATH="/usr/bin:/bin:$PATH"
export PYTHON_EXECUTABLE=/usr/bin/python3
unset PYTHONPATH PYENV_VERSION
export ROS_PYTHON_VERSION=3
