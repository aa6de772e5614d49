within Bicycle.Components;
model GyroscopicFrontFork "Front fork with the gyroscopic derivative term: delta = k1*T - k2*phi - k3*der(phi)"
  extends Bicycle.Icons.FrontFrameIcon;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.a "Horizontal distance a from the rear contact point P1 to the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.Length c(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.c "Trail c";
  parameter Bicycle.Units.Angle lambda(min = 1e-6, max = 1.5707963267948966) = Bicycle.Records.Astrom2005SecondOrder.lambda "Head angle lambda (90 deg is a vertical steer axis)";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  parameter Bicycle.Units.Time k3(min = 0) = Bicycle.Records.Astrom2005SecondOrder.k3 "Gain k3 of the gyroscopic derivative feedback from roll rate to steer angle";
  Bicycle.Interfaces.Roll roll "Roll axis"
    annotation(Placement(transformation(extent = {{-10, -110}, {10, -90}})));
  Bicycle.Interfaces.Steer steer "Steer axis"
    annotation(Placement(transformation(extent = {{-10, 90}, {10, 110}})));
  Bicycle.Interfaces.EffectiveSteerOutput front "Effective steer angle of the front wheel, eq (8)"
    annotation(Placement(transformation(origin = {-110, 40}, extent = {{-10, -10}, {10, 10}}, rotation = 180)));
  Bicycle.Interfaces.RollRateInput rollRate "Roll rate of the rear frame"
    annotation(Placement(transformation(extent = {{-140, -60}, {-100, -20}})));
  Bicycle.Components.StaticFrontFork contact(m = m, a = a, b = b, c = c, lambda = lambda, V = V, g = g) "Contact forces and steer geometry, eqs (7)-(13)"
    annotation(Placement(transformation(extent = {{-20, 0}, {20, 40}})));
  Bicycle.Components.FrontWheelGyroscope gyroscope(H_g = k3*m*a*c*sin(lambda)*(V^2*sin(lambda) - b*g*cos(lambda))/b^2) "Gyroscopic steer torque k3/k1(V)*der(phi)"
    annotation(Placement(transformation(extent = {{40, -60}, {80, -20}})));
equation
  connect(roll, contact.roll) annotation(Line(points = {{0, -100}, {0, 0}}, color = {0, 0, 0}));
  connect(steer, contact.steer) annotation(Line(points = {{0, 100}, {0, 40}}, color = {0, 0, 0}));
  connect(steer, gyroscope.steer) annotation(Line(points = {{0, 100}, {0, 80}, {60, 80}, {60, -20}}, color = {0, 0, 0}));
  connect(contact.front, front) annotation(Line(points = {{-22, 28}, {-60, 28}, {-60, 40}, {-110, 40}}, color = {0, 0, 127}));
  connect(rollRate, gyroscope.rollRate) annotation(Line(points = {{-120, -40}, {36, -40}}, color = {0, 0, 127}));
  annotation(
    Icon(graphics = {
      Ellipse(extent = {{30, -40}, {90, 20}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{40, -30}, {80, 10}}, lineColor = {95, 95, 95}, fillColor = {245, 245, 245}, fillPattern = FillPattern.Solid),
      Line(points = {{18.7, -25}, {25.1, -36.8}, {34.8, -46}, {46.8, -52}, {60, -54}, {73.2, -52}, {85.2, -46}, {94.9, -36.8}, {101.3, -25}}, color = {0, 0, 0}, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 6, smooth = Smooth.Bezier),
      Text(extent = {{40, 80}, {100, 40}}, textString = "k3", textColor = {64, 64, 64})}),
    Documentation(info = "<html>
<p>Section \"Gyroscopic Effects\": the static fork (11) with derivative feedback,
<code>delta = k1(V)*T - k2(V)*phi - k3*der(phi)</code>. The handlebar torque of the static fork,
<code>T = (delta + k2*phi)/k1</code>, gets the additional term <code>(k3/k1(V))*der(phi)</code> that
balances the gyroscopic torque of the front wheel, with
<code>1/k1(V) = m*a*c*sin(lambda)*(V^2*sin(lambda) - b*g*cos(lambda))/b^2</code> (12).
The paper gives no formula for <code>k3</code>, only that it is proportional to the angular
momentum of the front wheel (and hence to V); here it is a parameter [s].</p>
</html>"));
end GyroscopicFrontFork;
