within Bicycle.Linear;
model LinearizedFrontFrame "Front frame H: fork and handlebar, turning about the steer axis"
  extends Bicycle.Icons.FrontFrameIcon;
  extends Bicycle.Linear.PartialFrontBody(final S = 0);
  parameter Bicycle.Units.MomentOfInertia Iyy(min = 0) "Inertia-tensor element yy about the centre of mass (does not enter the linear model)";
  annotation(Documentation(info = "<html>
<p>Front fork with handlebar, without the front wheel: mass m, centre of mass (x, z), inertia-tensor
elements Ixx, Ixz, Izz about the centre of mass.</p>
</html>"));
end LinearizedFrontFrame;
