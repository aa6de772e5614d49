within Bicycle.Bicycles;
model RearSteered "Rear-wheel steered bicycle (18): model (1) at negative speed, steer angle in"
  parameter Bicycle.Units.Mass m(min = 1e-6) = 92 "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length h(min = 1e-6) = 1.0 "Height h of the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = 1.0 "Wheel base b";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = 96.7 "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = 46.3 "Inertia product D = -Jxz";
  parameter Bicycle.Units.Velocity V(max = 0) = -5 "Speed V of model (1), negative: the steered wheel trails (rear-wheel steering at forward speed -V)";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = 9.81 "Gravitational acceleration";
  input Bicycle.Units.Angle delta "Steer angle (vertical steer axis), positive steering to the left";
  output Bicycle.Units.Angle phi "Roll angle, positive leaning to the right";
  output Bicycle.Units.Angle psi "Yaw angle of the rear frame, positive to the left";
  output Bicycle.Units.Position eta "Path deviation of the rear contact point, positive to the left";
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
