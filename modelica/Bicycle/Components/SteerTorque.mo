within Bicycle.Components;
model SteerTorque "Torque applied by the rider to the handlebars"
  input Bicycle.Units.Torque T "Steer torque, positive counter-clockwise seen from above";
  Bicycle.Interfaces.Steer steer "Steer axis";
equation
  steer.tau = -T;
end SteerTorque;
