within Bicycle.Components;
model FrontWheelGyroscope "Gyroscopic torque of the spinning front wheel on the steer axis, proportional to the roll rate"
  extends Bicycle.Icons.Wheel;
  parameter Bicycle.Units.AngularMomentum H_g = 0 "Gyroscopic coefficient: steer torque per unit roll rate (proportional to the spin angular momentum of the front wheel)";
  Bicycle.Interfaces.Steer steer "Steer axis"
    annotation(Placement(transformation(extent = {{-10, 90}, {10, 110}})));
  Bicycle.Interfaces.RollRateInput rollRate "Roll rate of the rear frame"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
equation
  // A roll rate der(phi) makes the spinning wheel precess: gyroscopic torque -H_g*der(phi) about
  // the steer axis, which the handlebar torque has to balance.
  steer.tau = H_g*rollRate.omega;
  annotation(
    Icon(graphics = {
      Line(points = {{-20.5, 56.4}, {-36.5, 47.6}, {-49.1, 34.4}, {-57.2, 18}, {-60, 0}, {-57.2, -18}, {-49.1, -34.4}, {-36.5, -47.6}, {-20.5, -56.4}}, color = {255, 0, 0}, thickness = 0.75, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 8, smooth = Smooth.Bezier),
      Line(points = {{0, 16}, {0, 100}}, color = {95, 95, 95}, thickness = 0.5),
      Text(extent = {{-60, -20}, {60, -60}}, textString = "H_g", textColor = {0, 0, 0})}));
end FrontWheelGyroscope;
