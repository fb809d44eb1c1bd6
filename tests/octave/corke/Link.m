% One link of Peter Corke's Robotics Toolbox for MATLAB, as its documentation and his book
% (Robotics, Vision and Control, 2nd ed., sec. 7.1) define it; written for urdf2dh's tests, no
% code of the toolbox. Link(KIND, 'd', D, 'a', A, 'alpha', ALPHA, 'theta', THETA,
% 'offset', OFFSET, 'qlim', QLIM, FLAVOUR): KIND 'revolute' (the joint variable plus offset is
% theta) or 'prismatic' (it is d); FLAVOUR 'standard' (A = Rz(theta) Tz(d) Tx(a) Rx(alpha)) or
% 'modified' (A = Rx(alpha) Tx(a) Rz(theta) Tz(d), Craig's).
classdef Link
  properties
    theta = 0; d = 0; a = 0; alpha = 0; offset = 0; qlim = [];
    revolute = true; modified = false;
  end
  methods
    function L = Link(varargin)
      i = 1;
      while i <= numel(varargin)
        key = varargin{i};
        switch key
          case 'revolute', L.revolute = true;
          case 'prismatic', L.revolute = false;
          case 'standard', L.modified = false;
          case 'modified', L.modified = true;
          case {'theta', 'd', 'a', 'alpha', 'offset', 'qlim'}
            L.(key) = varargin{i + 1}; i = i + 1;
          otherwise, error('Link: option %s not understood', key);
        end
        i = i + 1;
      end
    end
    function T = A(L, q)
      theta = L.theta; d = L.d;
      if L.revolute, theta = q + L.offset; else, d = q + L.offset; end
      ct = cos(theta); st = sin(theta); ca = cos(L.alpha); sa = sin(L.alpha);
      Rz = [ct -st 0 0; st ct 0 0; 0 0 1 0; 0 0 0 1];
      Rx = [1 0 0 0; 0 ca -sa 0; 0 sa ca 0; 0 0 0 1];
      Tz = [1 0 0 0; 0 1 0 0; 0 0 1 d; 0 0 0 1];
      Tx = [1 0 0 L.a; 0 1 0 0; 0 0 1 0; 0 0 0 1];
      if L.modified, T = Rx * Tx * Rz * Tz; else, T = Rz * Tz * Tx * Rx; end
    end
  end
end
