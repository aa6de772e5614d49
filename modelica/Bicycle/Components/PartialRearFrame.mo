within Bicycle.Components;
partial model PartialRearFrame "Roll angular momentum balance of the rear frame with rider, eq (1) in momentum form (kinematics left to the extending model)"
  extends Bicycle.Icons.RearFrameIcon;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length h(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.h "Height h of the centre of mass above the ground";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J "Moment of inertia J about the x axis (whole bicycle with rider, steer angle zero)";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.D "Inertia product D = -Jxz with respect to the x and z axes";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V of the rear contact point (negative: the steered wheel trails, rear-wheel steering)";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  Bicycle.Units.Angle phi(start = 0) "Roll angle of the rear frame, positive leaning to the right";
  Bicycle.Units.AngularMomentum L(start = 0, fixed = true) "Angular momentum about the x axis less the steering term, L = J*der(chi) - D*V*delta_f/b";
  Bicycle.Units.AngularVelocity omega "Rate der(chi) of the inertia-weighted roll angle (the roll rate der(phi) when nothing moves relative to the frame)";
  Bicycle.Interfaces.Roll roll "Roll axis: external torques about the x axis act here"
    annotation(Placement(transformation(extent = {{-10, -110}, {10, -90}})));
  Bicycle.Interfaces.EffectiveSteerInput front "Effective steer angle delta_f of the front wheel, eq (8)"
    annotation(Placement(transformation(origin = {120, 40}, extent = {{-20, -20}, {20, 20}}, rotation = 180)));
equation
  // Momentum form of (1) with delta replaced by delta_f: the effective steer angle may be an
  // algebraic variable or an input, so der(delta_f) must not appear.
  omega = (L + D*V*front.delta_f/b)/J;
  der(L) = m*g*h*phi + m*V^2*h/b*front.delta_f + roll.tau;
  roll.phi = phi;
  annotation(Documentation(info = "<html>
<p>Angular momentum balance about the x axis of the rigid body formed by the frames, the wheels
and the rider (steer angle zero), eq (1) with the steer angle replaced by the effective steer
angle <code>delta_f</code> of (8):</p>
<pre>  J*der(chi) = L + D*V*delta_f/b
  der(L)     = m*g*h*phi + m*V^2*h/b*delta_f + roll.tau</pre>
<p><code>chi</code> is the roll angle <code>phi</code> itself in <code>RearFrame</code>; in
<code>RearFrameWithLean</code> it is the inertia-weighted roll angle of frame and leaning upper body.
The torques of the other components enter through <code>roll.tau</code>: the front fork adds
the torque <code>-m*g*a*c*sin(lambda)*delta/b</code> of the front contact point that moves with the
steer angle (together with <code>delta_f = delta*sin(lambda)</code> this turns (1) into (14)),
crowned rollers add <code>-m*g*R*phi</code> (27), a leaning rider adds <code>m_r*g*h_r*theta</code> (22).</p>
</html>"));
end PartialRearFrame;
