within Bicycle.Bicycles;
model SelfStabilizing "Rear frame (14) with static front fork (11): self-stabilizing bicycle with steer-torque input"
  parameter Bicycle.Units.Mass m = 92 "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a = 0.5 "Horizontal distance a from the rear contact point to the centre of mass";
  parameter Bicycle.Units.Length h = 1.0 "Height h of the centre of mass";
  parameter Bicycle.Units.Length b = 1.0 "Wheel base b";
  parameter Bicycle.Units.Length c = 0.08 "Trail c";
  parameter Bicycle.Units.Angle lambda = 1.2217304763960306 "Head angle lambda (70 deg)";
  parameter Bicycle.Units.MomentOfInertia J = 96.7 "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D = 46.3 "Inertia product D = -Jxz";
  parameter Bicycle.Units.Velocity V = 5 "Forward speed V";
  parameter Bicycle.Units.Acceleration g = 9.81 "Gravitational acceleration";
  input Bicycle.Units.Torque T "Steer torque applied to the handlebars";
  output Bicycle.Units.Angle phi "Roll angle, positive leaning to the right";
  output Bicycle.Units.Angle delta "Steer angle, positive steering to the left";
  Bicycle.Components.RearFrame frame(m = m, a = a, h = h, b = b, c = c, lambda = lambda, J = J, D = D, V = V, g = g) "Rear frame with rider";
  Bicycle.Components.StaticFrontFork fork(m = m, a = a, b = b, c = c, lambda = lambda, V = V, g = g) "Front fork";
  Bicycle.Components.SteerTorque handlebar(T = T) "Rider's steer torque";
equation
  connect(frame.roll, fork.roll);
  connect(frame.steer, fork.steer);
  connect(handlebar.steer, fork.steer);
  phi = frame.phi;
  delta = fork.steer.delta;
  annotation(
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>The bicycle of eqs (14) and (11): steer torque T in, roll angle phi and steer angle delta out.
Stable for V &gt; V_c = sqrt(b*g*cot(lambda)) (16) when b*h &gt; a*c*tan(lambda) (17).</p>
</html>"));
end SelfStabilizing;
