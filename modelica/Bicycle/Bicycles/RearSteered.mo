within Bicycle.Bicycles;
model RearSteered "Rear-wheel steered bicycle (18): model (1) at negative speed, steer angle in"
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length h(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.h "Height h of the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.D "Inertia product D = -Jxz";
  parameter Bicycle.Units.Velocity V(max = 0) = -Bicycle.Records.Astrom2005SecondOrder.V "Speed V of model (1), negative: the steered wheel trails (rear-wheel steering at forward speed -V)";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  Bicycle.Interfaces.RealInput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle (vertical steer axis), positive steering to the left";
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle, positive leaning to the right";
  Bicycle.Interfaces.RealOutput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Yaw angle of the rear frame, positive to the left";
  Bicycle.Interfaces.RealOutput eta(final quantity = "Length", final unit = "m") "Path deviation of the rear contact point, positive to the left";
  Bicycle.Components.RearFrame frame(m = m, h = h, b = b, J = J, D = D, V = V, g = g) "Rear frame with rider and wheels, eq (1)";
  Bicycle.Components.SteerAngle handlebar(delta = delta) "Rider's steer angle";
  Bicycle.Components.PathKinematics path(V = V, b = b) "Yaw angle and path deviation";
equation
  connect(handlebar.front, frame.front);
  connect(handlebar.front, path.front);
  phi = frame.phi;
  psi = path.psi;
  eta = path.eta;
  annotation(
    experiment(StartTime = 0, StopTime = 2, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Eq (18): reversing the sign of the velocity of model (1) gives the rear-steered bicycle,
G_phi_delta(s) = (-|V|*D*s + m*V^2*h)/(b*(J*s^2 - m*g*h)), with the pole sqrt(m*g*h/J) and the zero
m*|V|*h/D in the right half plane. Proportional steering delta = -k2*phi gives (19), unstable for
every k2 &gt; 0 and |V| &gt; 0. V is the speed of model (1) and must be negative (max = 0); psi and
eta follow the same reversed kinematics (der(eta) = V*psi).</p>
</html>"));
end RearSteered;
