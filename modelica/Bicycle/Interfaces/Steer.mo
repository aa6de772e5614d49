within Bicycle.Interfaces;
connector Steer "Steer axis: steer angle and torque about the steer axis"
  Bicycle.Units.Angle delta "Steer angle, positive steering to the left";
  flow Bicycle.Units.Torque tau "Torque about the steer axis acting on the component";
end Steer;
