within Bicycle.Components;
model GyroscopicFrontFork "Front fork with the gyroscopic derivative term: delta = k1*T - k2*phi - k3*der(phi)"
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.a "Horizontal distance a from the rear contact point P1 to the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.Length c(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.c "Trail c";
  parameter Bicycle.Units.Angle lambda(min = 1e-6, max = 1.5707963267948966) = Bicycle.Records.Astrom2005SecondOrder.lambda "Head angle lambda (90 deg is a vertical steer axis)";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  parameter Bicycle.Units.Time k3(min = 0) = Bicycle.Records.Astrom2005SecondOrder.k3 "Gain k3 of the gyroscopic derivative feedback from roll rate to steer angle";
  Bicycle.Interfaces.Roll roll "Roll axis";
  Bicycle.Interfaces.Steer steer "Steer axis";
  Bicycle.Interfaces.EffectiveSteerOutput front "Effective steer angle of the front wheel, eq (8)";
  Bicycle.Interfaces.RollRateInput rollRate "Roll rate of the rear frame";
  Bicycle.Components.StaticFrontFork contact(m = m, a = a, b = b, c = c, lambda = lambda, V = V, g = g) "Contact forces and steer geometry, eqs (7)-(13)";
  Bicycle.Components.FrontWheelGyroscope gyroscope(H_g = k3*m*a*c*sin(lambda)*(V^2*sin(lambda) - b*g*cos(lambda))/b^2) "Gyroscopic steer torque k3/k1(V)*der(phi)";
equation
  connect(roll, contact.roll);
  connect(steer, contact.steer);
  connect(steer, gyroscope.steer);
  connect(contact.front, front);
  connect(rollRate, gyroscope.rollRate);
  annotation(Documentation(info = "<html>
<p>Section \"Gyroscopic Effects\": the static fork (11) with derivative feedback,
<code>delta = k1(V)*T - k2(V)*phi - k3*der(phi)</code>. The handlebar torque of the static fork,
<code>T = (delta + k2*phi)/k1</code>, gets the additional term <code>(k3/k1(V))*der(phi)</code> that
balances the gyroscopic torque of the front wheel, with
<code>1/k1(V) = m*a*c*sin(lambda)*(V^2*sin(lambda) - b*g*cos(lambda))/b^2</code> (12).
The paper gives no formula for <code>k3</code>, only that it is proportional to the angular
momentum of the front wheel (and hence to V); here it is a parameter [s].</p>
</html>"));
end GyroscopicFrontFork;
