within Bicycle.Interfaces;
connector Roll "Roll axis of the rear frame: roll angle and torque about the x axis"
  Bicycle.Units.Angle phi "Roll angle of the rear frame, positive leaning to the right";
  flow Bicycle.Units.Torque tau "Torque about the roll (x) axis acting on the component";
end Roll;
