"""Robot wrappers: `Robot`, `Franka`, `WheeledRobot`, `ParallelGripper` (`robot`) and `SingleManipulator` (`manipulator`)."""
